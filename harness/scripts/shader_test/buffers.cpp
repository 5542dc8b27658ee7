// shader_test buffers, uniforms and textures: ssbo, ubo, push, uniform, atomic counters, texture.
#include "harness/scripts/shader_test/steps.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "harness/scripts/opengl_glsl.h"

namespace parity::harness::script::shader_test {

Pipeline* BufferCommands::pipeline(const std::string& name) {
  for (Pipeline& p : script_.pipelines)
    if (p.name == name) return &p;
  return nullptr;
}

// Buffers named by ssbo/ubo commands: "ssbo N", "ssbo SET:BINDING" or, for element E of a
// descriptor array, "ssbo SET:BINDING:E".
std::string BufferCommands::bufferFor(int line, const std::string& kind, const std::string& where, uint64_t extent) {
  uint32_t set = 0, binding = 0, element = 0;
  std::vector<uint32_t> parts;
  for (size_t at = 0;;) {
    const size_t colon = where.find(':', at);
    Value v;
    if (!parseNumber(where.substr(at, colon == std::string::npos ? std::string::npos : colon - at), &v) || !v.isInteger || v.i < 0)
      error(line, "expected BINDING, SET:BINDING or SET:BINDING:ELEMENT, got '" + where + "'");
    parts.push_back(static_cast<uint32_t>(v.i));
    if (colon == std::string::npos) break;
    at = colon + 1;
  }
  if (parts.size() > 3) error(line, "expected BINDING, SET:BINDING or SET:BINDING:ELEMENT, got '" + where + "'");
  if (parts.size() == 1) binding = parts[0];
  else set = parts[0], binding = parts[1];
  if (parts.size() == 3) element = parts[2];
  if (extent > kMaxBufferBytes) error(line, kind + " " + where + " of " + std::to_string(extent) + " bytes is too large");
  std::string name = kind + "_" + std::to_string(set) + "_" + std::to_string(binding);
  if (element) name += "_" + std::to_string(element);
  for (Buffer& existing : script_.buffers)
    if (existing.name == name) {
      if (existing.bytes.size() < extent) existing.bytes.resize(extent, 0);
      return name;
    }
  Buffer buf;
  buf.name = name;
  buf.hasType = true;
  std::string why;
  parseDataType("uint8", false, &buf.type, &why);
  buf.sized = true;
  buf.bytes.assign(std::max<uint64_t>(extent, 4), 0);
  buf.loc = {line, 1};
  script_.buffers.push_back(buf);
  for (Pipeline& p : script_.pipelines) {
    Bind bind;
    bind.kind = kind == "ssbo" ? BindKind::Storage : BindKind::Uniform;
    bind.asWord = kind == "ssbo" ? "storage" : "uniform";
    bind.buffer = name;
    bind.set = set, bind.binding = binding;
    bind.arrayElement = element;
    bind.loc = {line, 1};
    p.binds.push_back(bind);
  }
  return name;
}

std::string BufferCommands::pushBuffer(int line, uint64_t extent) {
  if (extent > 128) error(line, "push constants past byte 128");
  for (Buffer& existing : script_.buffers)
    if (existing.name == "push_constants") {
      if (existing.bytes.size() < extent) existing.bytes.resize(extent, 0);
      return existing.name;
    }
  Buffer buf;
  buf.name = "push_constants";
  buf.hasType = true;
  std::string why;
  parseDataType("uint8", false, &buf.type, &why);
  buf.sized = true;
  buf.bytes.assign(extent, 0);
  script_.buffers.push_back(buf);
  for (Pipeline& p : script_.pipelines) {
    Bind bind;
    bind.kind = BindKind::PushConstant;
    bind.asWord = "push_constant";
    bind.buffer = buf.name;
    p.binds.push_back(bind);
  }
  return buf.name;
}

ElementType BufferCommands::valueType(int line, const std::string& glsl, bool std140, bool rowMajor) {
  std::string amber = amberTypeName(glsl);
  ElementType t;
  std::string why;
  if (amber.empty() || !parseDataType(amber, std140, &t, &why)) error(line, "unknown type '" + glsl + "'");
  if (!rowMajor || t.columns == 1) return t;
  // A row-major matCxR is laid out as the column-major matRxC: values still come column by
  // column, so value (c, r) takes the transposed type's field (r, c).
  const std::string transposed = std::regex_replace(amber, std::regex(R"(mat(\d)x(\d))"), "mat$2x$1");
  ElementType rows;
  if (!parseDataType(transposed, std140, &rows, &why)) error(line, "unknown type '" + glsl + "'");
  const uint32_t C = t.columns, R = t.rows;
  for (uint32_t c = 0; c < C; ++c)
    for (uint32_t r = 0; r < R; ++r) t.layout.fields[c * R + r].offset = rows.layout.fields[r * C + c].offset;
  t.layout.stride = rows.layout.stride;
  return t;
}

ElementType BufferCommands::valueTypeIn(int line, const std::string& glsl, const std::string& kind) {
  const BlockLayout& layout = blockLayouts_.at(kind);
  return valueType(line, glsl, layout.std140, layout.rowMajor);
}

// ubo|ssbo|push layout [std140|std430] [row_major|column_major]: VkRunner's layouts of the
// values later commands write into or probe in that kind of buffer.
void BufferCommands::blockLayout(int line, const std::vector<std::string>& w) {
  BlockLayout& layout = blockLayouts_.at(w[0]);
  for (size_t i = 2; i < w.size(); ++i) {
    if (w[i] == "std140" || w[i] == "std430") layout.std140 = w[i] == "std140";
    else if (w[i] == "row_major" || w[i] == "column_major") layout.rowMajor = w[i] == "row_major";
    else error(line, w[0] + " layout: expected std140, std430, row_major or column_major, got '" + w[i] + "'");
  }
}

std::vector<Value> BufferCommands::numbers(int line, const std::vector<std::string>& w, size_t from) {
  std::vector<Value> out;
  for (size_t i = from; i < w.size(); ++i) {
    Value v;
    if (!parseNumber(w[i], &v)) error(line, "expected a number, got '" + w[i] + "'");
    out.push_back(v);
  }
  return out;
}

// Hexadecimal floats as their bits (applyHexFloatBits).
std::vector<Value> BufferCommands::typedNumbers(int line, const std::vector<std::string>& w, size_t from, const ElementType& type) {
  std::vector<Value> out = numbers(line, w, from);
  const std::vector<Field>& fields = type.layout.fields;
  for (size_t i = 0; i < out.size() && !fields.empty(); ++i)
    applyHexFloatBits(w[from + i], fields[i % fields.size()].scalar, &out[i]);
  return out;
}

// Values of `type` packed from byte 0 in the type's array stride.
std::vector<uint8_t> BufferCommands::pack(const ElementType& type, const std::vector<Value>& values) {
  std::vector<uint8_t> bytes;
  const Layout& L = type.layout;
  for (size_t i = 0; i < values.size(); ++i) {
    const Field& f = L.fields[i % L.fields.size()];
    storeValue(bytes, (i / L.fields.size()) * L.stride + f.offset, f.scalar, values[i]);
  }
  return bytes;
}

// `KIND TYPE OFFSET values` written into a buffer (ubo/ssbo subdata, push, VkRunner's uniform).
void BufferCommands::writeBuffer(int line, const std::string& kind, const std::string& where, const std::vector<std::string>& w, size_t typeAt) {
  if (w.size() < typeAt + 2) error(line, "expected TYPE OFFSET values");
  ElementType type = valueTypeIn(line, w[typeAt], kind);
  Value offset;
  if (!parseNumber(w[typeAt + 1], &offset) || !offset.isInteger || offset.i < 0) error(line, "expected a byte offset, got '" + w[typeAt + 1] + "'");
  std::vector<Value> values = typedNumbers(line, w, typeAt + 2, type);
  if (values.empty() || values.size() % type.layout.fields.size())
    error(line, std::to_string(values.size()) + " values for " + w[typeAt] + " (" + std::to_string(type.layout.fields.size()) + " per element)");
  Command c;
  c.kind = Command::Kind::WriteBuffer;
  c.loc = {line, 1};
  c.bytes = pack(type, values);
  c.px = static_cast<uint32_t>(offset.i);
  uint64_t extent = uint64_t(offset.i) + c.bytes.size();
  c.buffer = kind == "push" ? pushBuffer(line, extent) : bufferFor(line, kind, where, extent);
  if (!c.buffer.empty()) script_.commands.push_back(c);
}

// The atomic-counter buffer of OpenGL binding `binding` (piglit's atomics_bos[binding]).
std::string BufferCommands::atomicCounterBuffer(int line, uint32_t binding) {
  const std::string name = "atomic_counters_" + std::to_string(binding);
  if (script_.findBuffer(name)) return name;
  Buffer buf;
  buf.name = name;
  buf.hasType = buf.sized = true;
  std::string why;
  parseDataType("uint8", false, &buf.type, &why);
  buf.atomicCounterBinding = static_cast<int>(binding);
  buf.loc = {line, 1};
  script_.buffers.push_back(buf);
  return name;
}

// piglit's procedural textures (piglit-util-gl.c), as RGBA8 images on a texture unit, with the
// sampler state piglit gives them: `texture rgbw UNIT (W, H)` is red, green, blue and white
// quadrants (red at the first row and column), nearest, clamped to the edge;
// `texture quads UNIT LEVEL (W, H) (SX, SY) (bl) (br) (tl) (tr)` is squares of SX x SY, bl where
// the square's row and column (from the first row and column) are even, br at an odd column,
// tl at an odd row, tr where both are odd, nearest; `texture checkerboard UNIT LEVEL (W, H)
// (colour0) (colour1)` is quads of W/2 x H/2 with colour1 where exactly one is odd. piglit clamps
// both to a red border, which Vulkan's border colours cannot express: they are clamped to the
// edge here, which only differs for coordinates outside [0, 1].
void BufferCommands::texture(int line, const std::vector<std::string>& w) {
  if (w[1] == "miptree") return miptree(line, w);
  if (w[1] == "shadow1D" || w[1] == "shadow1DArray" || w[1] == "shadow2D" || w[1] == "shadowRect" || w[1] == "shadow2DArray")
    return shadowTexture(line, w);
  const bool checkerboard = w[1] == "checkerboard", quads = w[1] == "quads";
  Value first;
  if (w.size() > 2 && !parseNumber(w[2], &first)) return unsupported(line, "texture " + w[1] + " " + w[2]);  // 2DArray, 1D, ...
  std::vector<std::string> numeric(w.begin(), w.end());
  // An internal format after the size: RGBA8 is what piglit makes without one.
  std::string format = "R8G8B8A8_UNORM";
  if (w[1] == "rgbw" && numeric.size() == 6) {
    format = numeric.back() == "GL_RGBA32F" ? "R32G32B32A32_SFLOAT" : numeric.back() == "GL_RGBA8" || numeric.back() == "GL_RGBA" ? format : "";
    if (format.empty()) return unsupported(line, "texture rgbw " + numeric.back());
    numeric.pop_back();
  }
  std::vector<Value> v = numbers(line, numeric, 2);
  const size_t need = checkerboard ? 12 : quads ? 22 : 3;
  if (v.size() != need) error(line, "texture " + w[1] + " needs " + std::to_string(need) + " numbers");
  const int unit = static_cast<int>(v[0].i);
  const size_t size = checkerboard || quads ? 2 : 1;
  if (size == 2 && v[1].i != 0) return unsupported(line, "texture " + w[1] + " at mip level " + std::to_string(v[1].i));
  const uint32_t width = static_cast<uint32_t>(v[size].i), height = static_cast<uint32_t>(v[size + 1].i);
  if (width == 0 || height == 0 || width > kMaxImageDimension || height > kMaxImageDimension)
    error(line, "texture size out of range");
  if (uint64_t(width) * height * 16 > kMaxBufferBytes)  // RGBA32F at most
    error(line, "texture of " + std::to_string(uint64_t(width) * height) + " texels is too large");
  // Square sizes and the four colours (at v[first colour + 4k]) of the quads pattern.
  uint32_t squareWidth = std::max(1u, width / 2), squareHeight = std::max(1u, height / 2);
  std::array<size_t, 4> colourAt{4, 8, 8, 4};  // checkerboard: bl, br, tl, tr
  if (quads) {
    if (v[4].i <= 0 || v[5].i <= 0) error(line, "texture quads needs square sizes above 0");
    squareWidth = static_cast<uint32_t>(v[4].i), squareHeight = static_cast<uint32_t>(v[5].i);
    colourAt = {6, 10, 14, 18};
  }
  Buffer image = textureImage(line, unit, width, height, format);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      std::array<double, 4> c{};
      if (checkerboard || quads) {
        const size_t quadrant = ((y / squareHeight) & 1) * 2 + ((x / squareWidth) & 1);
        for (size_t i = 0; i < 4; ++i) c[i] = v[colourAt[quadrant] + i].d;
      } else {
        bool left = x < width / 2, bottom = y < height / 2;
        c = bottom ? (left ? std::array<double, 4>{1, 0, 0, 1} : std::array<double, 4>{0, 1, 0, 1})
                   : (left ? std::array<double, 4>{0, 0, 1, 1} : std::array<double, 4>{1, 1, 1, 1});
      }
      appendTexel(image, c);
    }
  placeTexture(line, image, unit);
}

// One RGBA texel of `image`'s format (RGBA8 or RGBA32F), from 0..1 components.
void BufferCommands::appendTexel(Buffer& image, const std::array<double, 4>& rgba) {
  for (double component : rgba) {
    if (image.type.layout.stride == 16) {
      const float f = static_cast<float>(component);
      const auto* bytes = reinterpret_cast<const uint8_t*>(&f);
      image.bytes.insert(image.bytes.end(), bytes, bytes + sizeof f);
    } else {
      image.bytes.push_back(static_cast<uint8_t>(std::lround(std::clamp(component, 0.0, 1.0) * 255.0)));
    }
  }
}

void BufferCommands::arrayTexture(int line, const std::vector<std::string>& w) {
  std::vector<Value> v = numbers(line, w, 3);
  if (v.size() != 4) error(line, "texture " + w[1] + " 2DArray needs a unit and (width, height, layers)");
  const int unit = static_cast<int>(v[0].i);
  const uint32_t width = static_cast<uint32_t>(v[1].i), height = static_cast<uint32_t>(v[2].i), layers = static_cast<uint32_t>(v[3].i);
  if (width == 0 || height == 0 || layers == 0 || width > kMaxImageDimension || height > kMaxImageDimension || layers > 2048)
    error(line, "texture size out of range");
  if (uint64_t(width) * height * layers * 4 > kMaxBufferBytes)
    error(line, "texture of " + std::to_string(uint64_t(width) * height * layers * 4) + " bytes is too large");
  Buffer image = textureImage(line, unit, width, height, "R8G8B8A8_UNORM");
  image.layers = layers;
  image.arrayTexture = true;
  static const std::array<std::array<double, 4>, 4> kLayerColours{{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}}};
  for (uint32_t layer = 0; layer < layers; ++layer)
    for (uint32_t texel = 0; texel < width * height; ++texel) appendTexel(image, w[1] == "junk" ? std::array<double, 4>{} : kLayerColours[layer % 4]);
  placeTexture(line, image, unit);
}

void BufferCommands::imageTexture(int line, const std::vector<std::string>& w) {
  Value unit;
  if (!parseNumber(w[2], &unit) || !unit.isInteger || unit.i < 0) error(line, "expected a texture unit, got '" + w[2] + "'");
  Buffer* texture = nullptr;
  for (Buffer& b : script_.buffers)
    if (b.textureUnit == unit.i) texture = &b;
  if (!texture) error(line, "image texture " + w[2] + ": no texture command filled unit " + w[2]);
  // The format the image unit reads the texture as: piglit's files give the texture's own.
  static const std::map<std::string, std::string> kFormats = {{"GL_RGBA8", "R8G8B8A8_UNORM"}, {"GL_RGBA32F", "R32G32B32A32_SFLOAT"}};
  if (w.size() > 3) {
    auto format = kFormats.find(w[3]);
    if (format == kFormats.end() || format->second != texture->type.name) return unsupported(line, "image texture " + w[2] + " " + w[3]);
  }
  texture->imageUnit = static_cast<int>(unit.i);
}

// piglit's miptree texture (piglit_miptree_texture): 8x8 with its 4 levels, red, green, blue and
// white, sampled nearest within and between levels.
void BufferCommands::miptree(int line, const std::vector<std::string>& w) {
  std::vector<Value> v = numbers(line, w, 2);
  // shader_runner reads the unit only; later files add the size, which is always (8, 8).
  if (v.size() != 1 && v.size() != 3) error(line, "texture miptree needs a texture unit (and nothing or its size)");
  if (v.size() == 3 && (v[1].i != 8 || v[2].i != 8)) error(line, "texture miptree is 8x8 (piglit_miptree_texture)");
  const int unit = static_cast<int>(v[0].i);
  Buffer image = textureImage(line, unit, 8, 8, "R8G8B8A8_UNORM");
  image.mipLevels = 4;
  const std::array<std::array<uint8_t, 4>, 4> colours{{{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}}};
  for (uint32_t level = 0, size = 8; level < 4; ++level, size /= 2)
    for (uint32_t texel = 0; texel < size * size; ++texel) image.bytes.insert(image.bytes.end(), colours[level].begin(), colours[level].end());
  placeTexture(line, image, unit);
  for (Sampler& sampler : script_.samplers)
    if (sampler.textureUnit == unit) sampler.mipmapMode = "nearest";
}

// piglit's depth textures (piglit_depth_texture): 32-bit float depth rising from 0 in the left
// column to 1 in the right one, compared with GL_GREATER. A rectangle texture is a 2D texture
// here: its shaders' texel coordinates are normalised where they are sampled (opengl_glsl.cpp).
void BufferCommands::shadowTexture(int line, const std::vector<std::string>& w) {
  // piglit_depth_texture: a gradient from 0 at the left to 1 at the right, the same in every layer.
  // shadow1DArray's size is (width, layers).
  const bool array = w[1] == "shadow2DArray" || w[1] == "shadow1DArray";
  const bool oneDimensional = w[1] == "shadow1D" || w[1] == "shadow1DArray";
  const size_t sizes = 1 + (oneDimensional ? 0 : 1) + (array ? 1 : 0);
  std::vector<Value> v = numbers(line, w, 2);
  if (v.size() != 1 + sizes)
    error(line, "texture " + w[1] + " needs a unit and (width" + (oneDimensional ? "" : ", height") + (array ? ", layers)" : ")"));
  const int unit = static_cast<int>(v[0].i);
  const uint32_t width = static_cast<uint32_t>(v[1].i), height = oneDimensional ? 1 : static_cast<uint32_t>(v[2].i);
  const uint32_t layers = array ? static_cast<uint32_t>(v[sizes].i) : 1;
  if (width < 2 || height == 0 || layers == 0 || width > kMaxImageDimension || height > kMaxImageDimension || layers > 2048)
    error(line, "texture size out of range");
  if (uint64_t(width) * height * layers * 4 > kMaxBufferBytes)
    error(line, "texture of " + std::to_string(uint64_t(width) * height * layers * 4) + " bytes is too large");
  Buffer image = textureImage(line, unit, width, height, "D32_SFLOAT");
  image.layers = layers;
  image.arrayTexture = array;
  if (oneDimensional) image.dim = "DIM_1D";
  for (uint32_t texel = 0; texel < width * height * layers; ++texel) {
    const float depth = static_cast<float>(texel % width) / static_cast<float>(width - 1);
    const auto* bytes = reinterpret_cast<const uint8_t*>(&depth);
    image.bytes.insert(image.bytes.end(), bytes, bytes + sizeof depth);
  }
  placeTexture(line, image, unit);
  for (Sampler& sampler : script_.samplers)
    if (sampler.textureUnit == unit) sampler.compare = true, sampler.compareOp = "greater";
}

// An image of piglit's texture on `unit`, without its texels.
Buffer BufferCommands::textureImage(int line, int unit, uint32_t width, uint32_t height, const std::string& format) {
  Buffer image;
  image.name = "texture_unit_" + std::to_string(unit);
  image.isImage = image.hasType = image.sized = true;
  image.textureUnit = unit;
  image.width = width, image.height = height;
  image.loc = {line, 1};
  std::string why;
  parseFormat(format, &image.type, &why);
  return image;
}

// The texture on `unit` from now on, with a sampler in GL's state for it: clamped to the edge,
// nearest without mipmapping, no level-of-detail clamp of its own (GL's MAX_LOD is 1000).
void BufferCommands::placeTexture(int line, const Buffer& image, int unit) {
  Sampler sampler;
  sampler.name = "sampler_unit_" + std::to_string(unit);
  sampler.textureUnit = unit;
  sampler.addressMode = {"clamp_to_edge", "clamp_to_edge", "clamp_to_edge"};
  sampler.mipmapMode = "none";
  sampler.minLod = -1000.0, sampler.maxLod = 1000.0;
  sampler.loc = {line, 1};
  // A later texture on the same unit replaces the earlier one.
  script_.buffers.erase(std::remove_if(script_.buffers.begin(), script_.buffers.end(), [&](const Buffer& b) { return b.textureUnit == unit; }),
                        script_.buffers.end());
  script_.samplers.erase(std::remove_if(script_.samplers.begin(), script_.samplers.end(), [&](const Sampler& x) { return x.textureUnit == unit; }),
                         script_.samplers.end());
  script_.buffers.push_back(image);
  script_.samplers.push_back(sampler);
  lastTextureUnit_ = unit;
}

// texparameter TARGET PARAMETER VALUE...: the state of the last texture's unit, as piglit's
// shader_runner sets it: filters, wrap modes, the border colour, the comparison, the levels
// sampled (base_level, max_level), the level-of-detail bias, the swizzle or the depth texture
// mode.
void BufferCommands::texparameter(int line, const std::vector<std::string>& w) {
  static const std::set<std::string> kTargets = {"1D", "2D", "3D", "Rect", "Cube", "1DArray", "2DArray", "CubeArray"};
  if (!kTargets.count(w[1])) error(line, "unknown texture target '" + w[1] + "'");
  auto forUnit = [&](auto&& set) {
    for (Sampler& sampler : script_.samplers)
      if (sampler.textureUnit == lastTextureUnit_) set(sampler);
  };
  if (w[2] == "wrap_s" || w[2] == "wrap_t" || w[2] == "wrap_r") {
    if (w[3] != "repeat" && w[3] != "clamp_to_edge" && w[3] != "clamp_to_border") error(line, "unknown " + w[2] + " '" + w[3] + "'");
    const size_t axis = w[2] == "wrap_s" ? 0 : w[2] == "wrap_t" ? 1 : 2;
    return forUnit([&](Sampler& sampler) { sampler.addressMode[axis] = w[3]; });
  }
  if (w[2] == "base_level" || w[2] == "max_level") {
    Value level;
    if (!parseNumber(w[3], &level) || !level.isInteger || level.i < 0 || level.i > 1000)
      error(line, "expected a mip level, got '" + w[3] + "'");
    return forUnit([&](Sampler& sampler) { (w[2] == "base_level" ? sampler.baseLevel : sampler.maxLevel) = static_cast<uint32_t>(level.i); });
  }
  if (w[2] == "border_color") {
    const std::vector<Value> c = numbers(line, w, 3);
    if (c.size() != 4) error(line, "texparameter border_color needs 4 numbers");
    static const std::map<std::array<double, 4>, std::string> kColours = {{{0, 0, 0, 0}, "float_transparent_black"},
                                                                          {{0, 0, 0, 1}, "float_opaque_black"},
                                                                          {{1, 1, 1, 1}, "float_opaque_white"}};
    auto colour = kColours.find({c[0].d, c[1].d, c[2].d, c[3].d});
    if (colour == kColours.end())
      return unsupported(line, "texparameter border_color (the RHI's border colours are transparent black, opaque black and opaque white)");
    return forUnit([&](Sampler& sampler) { sampler.borderColor = colour->second; });
  }
  if (w.size() != 4) error(line, "expected texparameter TARGET PARAMETER VALUE");
  if (w[2] == "compare_func") {
    static const std::map<std::string, std::string> kOps = {
        {"never", "never"},     {"less", "less"},         {"equal", "equal"},   {"lequal", "less_or_equal"},
        {"greater", "greater"}, {"notequal", "not_equal"}, {"gequal", "greater_or_equal"}, {"always", "always"}};
    auto op = kOps.find(w[3]);
    if (op == kOps.end()) error(line, "unknown compare_func '" + w[3] + "'");
    for (Sampler& sampler : script_.samplers)
      if (sampler.textureUnit == lastTextureUnit_) sampler.compareOp = op->second;
    return;
  }
  if (w[2] == "depth_mode") return depthMode(line, w[3]);
  if (w[2] == "swizzle_r" || w[2] == "swizzle_g" || w[2] == "swizzle_b" || w[2] == "swizzle_a") {
    static const std::set<std::string> kSources = {"red", "green", "blue", "alpha", "zero", "one"};
    if (!kSources.count(w[3])) error(line, "unknown " + w[2] + " '" + w[3] + "'");
    const size_t component = std::string("rgba").find(w[2].back());
    return forUnit([&](Sampler& sampler) { sampler.swizzle[component] = w[3]; });
  }
  if (w[2] == "lod_bias") {
    Value bias;
    if (!parseNumber(w[3], &bias)) error(line, "expected a level-of-detail bias, got '" + w[3] + "'");
    return forUnit([&](Sampler& sampler) { sampler.lodBias = bias.d; });
  }
  // min: nearest, linear, or FILTER_mipmap_MIPFILTER; mag: nearest or linear.
  std::string filter = w[3], mipmap = "none";
  if (const size_t at = filter.find("_mipmap_"); at != std::string::npos && w[2] == "min") {
    mipmap = filter.substr(at + 8);
    filter = filter.substr(0, at);
  }
  if (w[2] != "min" && w[2] != "mag") return unsupported(line, "texparameter " + w[2]);
  if ((filter != "nearest" && filter != "linear") || (mipmap != "none" && mipmap != "nearest" && mipmap != "linear"))
    error(line, "unknown " + w[2] + " filter '" + w[3] + "'");
  for (Sampler& sampler : script_.samplers) {
    if (sampler.textureUnit != lastTextureUnit_) continue;
    (w[2] == "min" ? sampler.linearMin : sampler.linearMag) = filter == "linear";
    if (w[2] == "min") sampler.mipmapMode = mipmap;
  }
}

// The compatibility profile's GL_DEPTH_TEXTURE_MODE of the texture on the current unit: how a
// shadow2D*() result fills a vec4. The GLSL for it reads parity_depth_mode_SAMPLER
// (opengl_glsl.h's DepthTextureMode), written here for each shadow sampler on that unit.
void BufferCommands::depthMode(int line, const std::string& mode) {
  static const std::map<std::string, int> kModes = {{"luminance", int(DepthTextureMode::Luminance)},
                                                    {"intensity", int(DepthTextureMode::Intensity)},
                                                    {"alpha", int(DepthTextureMode::Alpha)},
                                                    {"red", int(DepthTextureMode::Red)}};
  auto m = kModes.find(mode);
  if (m == kModes.end()) error(line, "unknown depth_mode '" + mode + "'");
  // An assembly program reads the texture's own mode, the compatibility context's luminance.
  if (script_.hasArbPrograms() && m->second != int(DepthTextureMode::Luminance))
    return unsupported(line, "texparameter depth_mode " + mode + " with ARB assembly programs");
  for (const Shader& shader : script_.shaders)
    for (const std::string& sampler : depthModeSamplers(shader.source)) {
      auto unit = samplerUnits_.find(sampler);
      if (unit == samplerUnits_.end() || unit->second != lastTextureUnit_) continue;
      setUniform(line, {"uniform", "int", depthModeUniform(sampler), std::to_string(m->second)});
    }
}

// piglit: uniform TYPE NAME values
void BufferCommands::setUniform(int line, const std::vector<std::string>& w) {
  std::string amber = amberTypeName(w[1]);
  if (amber.empty()) return unsupported(line, "uniform " + w[1]);
  if (w[1] == "int" && w.size() == 4) {
    Value unit;  // a sampler's texture unit, perhaps
    if (parseNumber(w[3], &unit)) samplerUnits_[w[2]] = static_cast<int>(unit.i);
  }
  Command c;
  c.kind = Command::Kind::SetUniform;
  c.loc = {line, 1};
  c.uniform = w[2];
  c.arrayElement = uboArrayIndex_;
  c.valueType = valueType(line, w[1], true);
  c.valueTypeGiven = true;
  // piglit sets as many components as are given (some of its files give fewer than the type has).
  c.values = typedNumbers(line, w, 3, c.valueType);
  if (c.values.empty()) error(line, "uniform " + w[2] + " needs values");
  script_.commands.push_back(c);
}

}  // namespace parity::harness::script::shader_test
