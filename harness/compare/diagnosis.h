// Names the likely cause of a failed comparison by testing transformed candidates: each
// candidate applies one classic porting bug to the golden (a flip, a shift, a swizzle, an sRGB
// conversion too many or too few, a range scale, lost precision) and checks whether that
// explains the rendered image. A candidate is named only when it explains nearly all of the
// difference, so a genuine regression (a light missing, a material changed) gets no name.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

namespace parity::harness {

struct Diagnosis {
  std::string cause;     // stable name, e.g. "vertical flip", "precision loss of 3 bits"
  std::string detail;    // one line: how well the candidate explains the difference
  double baseline = 0;   // mean absolute difference golden vs image (interior, RGB)
  double residual = 0;   // the same after applying the candidate to the golden
};

// The classes a diagnosis can name (the prefix of Diagnosis::cause).
const std::vector<std::string>& diagnosisClasses();

// Null when the images match, differ in size, or no candidate explains the difference.
std::optional<Diagnosis> diagnose(const OIIO::ImageBuf& golden, const OIIO::ImageBuf& image);

nlohmann::json toJson(const Diagnosis& d);

}  // namespace parity::harness
