// The on-disk cache of compiled shaders, shared by every parity process of a machine: a `parity
// run` starts hundreds of children, and each would otherwise compile the same GLSL again. It holds
// glslang's SPIR-V (rhi/shader_compiler.cpp) and the GL backend's SPIRV-Cross translations of
// SPIR-V to GLSL (rhi/gl/gl_shader.cpp); each key names its producer, that producer's version and
// a hash of parity's code around it (PARITY_SHADER_CACHE_STAMP, CMakeLists.txt).
//
// An entry is found by a hash of its key and holds the key itself, so a hash collision or a
// damaged file is never mistaken for a hit: the key is compared in full and the bytes checked
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

// The bytes stored under `key`, if a whole, matching entry is there.
std::optional<std::string> loadCachedBytes(const std::string& key);
// Stores `bytes` under `key` (best effort: a full disk or a read-only folder only costs speed).
void storeCachedBytes(const std::string& key, const std::string& bytes);

// The same for SPIR-V words.
std::optional<std::vector<uint32_t>> loadCachedWords(const std::string& key);
void storeCachedWords(const std::string& key, const std::vector<uint32_t>& words);

}  // namespace parity::rhi
