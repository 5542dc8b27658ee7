// The on-disk cache of compiled shaders, shared by every parity process of a machine: a `parity
// run` starts hundreds of children, and each would otherwise compile the same GLSL again.
//
// An entry is found by a hash of its key and holds the key itself, so a hash collision or a
// damaged file is never mistaken for a hit: the key is compared in full and the words checked
// against a checksum; anything else is a miss, and the caller compiles and stores again. Entries
// are written to a temporary file and renamed into place, so concurrent processes see either no
// entry or a whole one.
//
// Folder: $PARITY_SHADER_CACHE, else $XDG_CACHE_HOME/parity/shaders, else
// $HOME/.cache/parity/shaders. PARITY_SHADER_CACHE=off (or empty) turns the cache off.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace parity::rhi {

// The cache folder, or "" when the cache is off.
std::string shaderCacheDirectory();

// The words stored under `key`, if a whole, matching entry is there.
std::optional<std::vector<uint32_t>> loadCachedWords(const std::string& key);
// Stores `words` under `key` (best effort: a full disk or a read-only folder only costs speed).
void storeCachedWords(const std::string& key, const std::vector<uint32_t>& words);

}  // namespace parity::rhi
