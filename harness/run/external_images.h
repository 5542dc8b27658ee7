// Renders another program made (`parity run --images DIR`), judged exactly like parity's own
// cases: goldens and bless with provenance, GL vs Vulkan and the triangulated verdict, FLIP,
// diagnosis, expectations, junit/JSON/HTML reports, shards and merge. Layout (docs/HARNESS.md,
// "External images"):
//   DIR/<technique>/<scene>/<platform>/<backend>.png          the image of one case
//   DIR/<technique>/<scene>/<platform>/<backend>.repeat.png   optional: a second render of it,
//                                                             compared bit for bit (determinism)
//   DIR/devices.json   optional: {"<backend>": {"renderer": ..., "driver": ..., "api": ...}}
// <technique>, <scene> and <platform> are the other program's names (a platform need not be one
// of parity's); <backend> is gl or vk for the GL/Vulkan comparison, any other name is compared
// with its golden only.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/run.h"

namespace parity::harness {

// Every case of DIR the filters and the shard select, grouped so that both backends of a group
// land in one shard. Fails (with a one-line error naming the file) on a malformed layout or
// devices.json, or when DIR holds no image.
std::vector<CaseKey> enumerateImageCases(const std::string& dir, const RunFilters& filters, const Shard& shard,
                                         std::string* error);

// Copies the case's image to `imageOut` and describes it as a render child would: device (from
// devices.json), "deterministic", "renders". Fails when the image cannot be read as an image.
bool loadExternalCase(const std::string& dir, const CaseKey& key, const std::string& imageOut, nlohmann::json* worker,
                      std::string* error);

}  // namespace parity::harness
