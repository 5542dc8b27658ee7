// Scenes from files: glTF 2.0 through tinygltf, OBJ + MTL through tinyobjloader (both Debian
// packages). Everything ends up as the same world-space Scene the procedural default produces.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include "scene/scene.h"

namespace parity::scene {

namespace {

namespace fs = std::filesystem;

// The specular colour and power of materials whose file has none (glTF has no Phong terms).
const glm::vec3 kDefaultSpecular{0.2f};
constexpr float kDefaultSpecularPower = 32.0f;

// First line of a (possibly multi-line) message from a loader, without trailing blanks.
std::string firstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
  return line;
}

struct LoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Resource limits: scene files come from pull requests, so sizes and counts taken from a file are
// bounded before anything is allocated from them. Each is far above the largest model in use
// (Sponza: 262k triangles, 2k x 2k textures, a 20 MB OBJ).
constexpr uintmax_t kMaxFileBytes = 512ull << 20;   // any file a scene reads
constexpr size_t kMaxAccessorElements = 1ull << 24;  // vertices or indices of one accessor
constexpr size_t kMaxSceneVertices = 1ull << 25;     // all meshes together
constexpr uint32_t kMaxTextureSide = 16384;
constexpr size_t kMaxByteStride = 1u << 12;

// Files a scene references (glTF buffers and images, OBJ material libraries and textures) must
// lie inside the scene file's folder tree: no absolute paths, no `..` out of it and no symlink
// that leads out of it. `root` is the canonical folder of the scene file.
std::string confinedPath(const fs::path& root, const std::string& reference) {
  if (reference.empty()) throw LoadError("empty file reference");
  fs::path ref(reference);
  if (ref.is_absolute() || ref.has_root_name() || ref.has_root_directory())
    throw LoadError("'" + reference + "' is an absolute path (references must stay inside the scene's folder)");
  std::error_code ec;
  // weakly_canonical resolves every symlink of the part that exists, so a link pointing out of
  // the tree is judged by where it leads.
  fs::path resolved = fs::weakly_canonical(root / ref, ec);
  if (ec) throw LoadError("'" + reference + "' cannot be resolved: " + ec.message());
  auto [rootEnd, at] = std::mismatch(root.begin(), root.end(), resolved.begin(), resolved.end());
  if (rootEnd != root.end())
    throw LoadError("'" + reference + "' is outside the scene's folder (`..` or a symlink out of it)");
  return resolved.string();
}

// Reads a whole file, bounded by kMaxFileBytes.
bool readBoundedFile(const std::string& path, std::vector<unsigned char>* out, std::string* error) {
  std::error_code ec;
  uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    *error = "'" + path + "' cannot be read: " + ec.message();
    return false;
  }
  if (size > kMaxFileBytes) {
    *error = "'" + path + "' is larger than " + std::to_string(kMaxFileBytes >> 20) + " MiB";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    *error = "'" + path + "' cannot be read";
    return false;
  }
  return true;
}

// The width and height a PNG header declares, checked before the decoder allocates for them.
void checkImageHeader(const std::string& name, const unsigned char* bytes, size_t size) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 24 && std::memcmp(bytes, kPng, 8) == 0) {
    auto be32 = [&](size_t at) {
      return uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 | uint32_t(bytes[at + 2]) << 8 | bytes[at + 3];
    };
    uint32_t w = be32(16), h = be32(20);
    if (w > kMaxTextureSide || h > kMaxTextureSide)
      throw LoadError("texture '" + name + "' is " + std::to_string(w) + "x" + std::to_string(h) +
                      " (larger than " + std::to_string(kMaxTextureSide) + " in a dimension)");
  }
}

// Decodes PNG/JPEG/... bytes to RGBA8 with the image decoder tinygltf ships with.
Texture decodeTexture(const std::string& name, const std::vector<unsigned char>& bytes) {
  tinygltf::Image image;
  std::string err, warn;
  checkImageHeader(name, bytes.data(), bytes.size());
  if (bytes.empty() || !tinygltf::LoadImageData(&image, 0, &err, &warn, 0, 0, bytes.data(),
                                                static_cast<int>(bytes.size()), nullptr))
    throw LoadError("texture '" + name + "' cannot be decoded" + (err.empty() ? "" : ": " + firstLine(err)));
  Texture t;
  t.name = name;
  t.width = static_cast<uint32_t>(image.width);
  t.height = static_cast<uint32_t>(image.height);
  size_t texels = static_cast<size_t>(t.width) * t.height;
  t.rgba8.resize(texels * 4);
  int comp = image.component;
  bool sixteen = image.bits == 16;
  if (comp < 1 || comp > 4 || image.image.size() < texels * comp * (sixteen ? 2 : 1))
    throw LoadError("texture '" + name + "' has an unsupported pixel layout");
  for (size_t i = 0; i < texels; ++i) {
    uint8_t c[4] = {0, 0, 0, 255};
    for (int k = 0; k < comp; ++k) {
      size_t at = i * comp + k;
      c[k] = sixteen ? image.image[at * 2 + 1] : image.image[at];  // little-endian: high byte second
    }
    if (comp <= 2) {  // grey (+ alpha)
      uint8_t a = comp == 2 ? c[1] : 255;
      c[1] = c[2] = c[0];
      c[3] = a;
    }
    std::memcpy(&t.rgba8[i * 4], c, 4);
  }
  return t;
}

// True when every texel has R = G = B: a height map rather than a normal map.
bool isGrey(const Texture& t) {
  for (size_t i = 0; i + 3 < t.rgba8.size(); i += 4)
    if (t.rgba8[i] != t.rgba8[i + 1] || t.rgba8[i] != t.rgba8[i + 2]) return false;
  return true;
}

// Slope of the height field per texel at bump multiplier 1, heights in [0, 1]: a heuristic
// strength (the full height range rises over 8 texels), as the MTL format defines none.
constexpr float kHeightSlopeScale = 8.0f;

// A tangent-space normal map (normal_mapping.glsl's convention: +x right, +y towards row 0) from
// a grey height map, by central differences with wrap-around (the material sampler repeats).
Texture normalMapFromHeights(const Texture& heights, float bumpMultiplier) {
  Texture t = heights;
  const uint32_t w = heights.width, h = heights.height;
  auto height = [&](uint32_t x, uint32_t y) { return heights.rgba8[(static_cast<size_t>(y) * w + x) * 4] / 255.0f; };
  const float strength = kHeightSlopeScale * bumpMultiplier;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float dhdx = 0.5f * (height((x + 1) % w, y) - height((x + w - 1) % w, y));
      float dhdRow = 0.5f * (height(x, (y + 1) % h) - height(x, (y + h - 1) % h));
      // Rising to the right tilts the normal left; rising downwards (+row) tilts it up (+y).
      glm::vec3 n = glm::normalize(glm::vec3(-dhdx * strength, dhdRow * strength, 1.0f));
      uint8_t* texel = &t.rgba8[(static_cast<size_t>(y) * w + x) * 4];
      for (int k = 0; k < 3; ++k) texel[k] = static_cast<uint8_t>(std::lround((n[k] * 0.5f + 0.5f) * 255.0f));
      texel[3] = 255;
    }
  return t;
}

// Adds per-vertex normals (area-weighted face normals) to vertices that have none.
void computeNormals(std::vector<Vertex>& vertices, const std::vector<uint32_t>& indices, size_t firstVertex,
                    size_t firstIndex) {
  for (size_t v = firstVertex; v < vertices.size(); ++v) vertices[v].normal = glm::vec3(0.0f);
  for (size_t i = firstIndex; i + 2 < indices.size(); i += 3) {
    Vertex& a = vertices[indices[i]];
    Vertex& b = vertices[indices[i + 1]];
    Vertex& c = vertices[indices[i + 2]];
    glm::vec3 n = glm::cross(b.position - a.position, c.position - a.position);
    a.normal += n;
    b.normal += n;
    c.normal += n;
  }
  for (size_t v = firstVertex; v < vertices.size(); ++v) {
    float len = glm::length(vertices[v].normal);
    vertices[v].normal = len > 0.0f ? vertices[v].normal / len : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

void finishMesh(Scene& s, Mesh mesh, size_t firstVertex) {
  mesh.indexCount = static_cast<uint32_t>(s.indices.size()) - mesh.firstIndex;
  if (mesh.indexCount == 0) return;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (size_t i = mesh.firstIndex; i < s.indices.size(); ++i) {
    lo = glm::min(lo, s.vertices[s.indices[i]].position);
    hi = glm::max(hi, s.vertices[s.indices[i]].position);
  }
  (void)firstVertex;
  mesh.boundsMin = lo;
  mesh.boundsMax = hi;
  s.meshes.push_back(mesh);
}

// ---- glTF 2.0 ----

// Reads `count` elements of an accessor as floats (normalised integers are mapped to [0, 1]).
std::vector<float> readAccessor(const tinygltf::Model& m, int accessorIndex, int wantComponents,
                                const std::string& what) {
  if (accessorIndex < 0 || accessorIndex >= static_cast<int>(m.accessors.size()))
    throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " does not exist");
  const tinygltf::Accessor& a = m.accessors[static_cast<size_t>(accessorIndex)];
  int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  int componentSize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (components != wantComponents || componentSize <= 0)
    throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " has an unexpected type");
  if (a.count > kMaxAccessorElements)
    throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " has " + std::to_string(a.count) +
                    " elements (limit " + std::to_string(kMaxAccessorElements) + ")");
  std::vector<float> out(a.count * static_cast<size_t>(components), 0.0f);
  if (a.bufferView < 0) return out;  // all zeros (sparse accessors without a view are not used here)
  if (a.sparse.isSparse) throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " is sparse (not supported)");
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<size_t>(a.bufferView));
  if (view.buffer < 0 || view.buffer >= static_cast<int>(m.buffers.size()))
    throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " names a missing buffer");
  const tinygltf::Buffer& buffer = m.buffers[static_cast<size_t>(view.buffer)];
  size_t elementSize = static_cast<size_t>(components) * static_cast<size_t>(componentSize);
  size_t stride = view.byteStride ? view.byteStride : elementSize;
  // Bounded first, so that the end computed below cannot wrap around.
  if (stride > kMaxByteStride || view.byteOffset > buffer.data.size() || a.byteOffset > buffer.data.size())
    throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " has an offset or stride out of range");
  size_t start = view.byteOffset + a.byteOffset;
  if (a.count > 0) {
    size_t end = start + (a.count - 1) * stride + elementSize;
    if (end > view.byteOffset + view.byteLength || end > buffer.data.size())
      throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " reads past the end of buffer " +
                      std::to_string(view.buffer) + " (truncated file?)");
  }
  for (size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = buffer.data.data() + start + i * stride;
    for (int k = 0; k < components; ++k) {
      const unsigned char* c = p + static_cast<size_t>(k) * static_cast<size_t>(componentSize);
      float v = 0.0f;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, c, 4); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = c[0] / 255.0f; break;
        case TINYGLTF_COMPONENT_TYPE_BYTE: v = std::max(static_cast<int8_t>(c[0]) / 127.0f, -1.0f); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t x;
          std::memcpy(&x, c, 2);
          v = x / 65535.0f;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          int16_t x;
          std::memcpy(&x, c, 2);
          v = std::max(x / 32767.0f, -1.0f);
          break;
        }
        default: throw LoadError(what + " accessor " + std::to_string(accessorIndex) + " has an unsupported component type");
      }
      out[i * static_cast<size_t>(components) + static_cast<size_t>(k)] = v;
    }
  }
  return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& m, int accessorIndex) {
  if (accessorIndex < 0 || accessorIndex >= static_cast<int>(m.accessors.size()))
    throw LoadError("index accessor " + std::to_string(accessorIndex) + " does not exist");
  const tinygltf::Accessor& a = m.accessors[static_cast<size_t>(accessorIndex)];
  if (a.bufferView < 0 || a.type != TINYGLTF_TYPE_SCALAR) throw LoadError("index accessor " + std::to_string(accessorIndex) + " is invalid");
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<size_t>(a.bufferView));
  if (view.buffer < 0 || view.buffer >= static_cast<int>(m.buffers.size()))
    throw LoadError("index accessor " + std::to_string(accessorIndex) + " names a missing buffer");
  const tinygltf::Buffer& buffer = m.buffers[static_cast<size_t>(view.buffer)];
  size_t size = static_cast<size_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType)));
  if (size != 1 && size != 2 && size != 4) throw LoadError("index accessor " + std::to_string(accessorIndex) + " has an unsupported type");
  size_t stride = view.byteStride ? view.byteStride : size;
  if (a.count > kMaxAccessorElements || stride > kMaxByteStride || view.byteOffset > buffer.data.size() ||
      a.byteOffset > buffer.data.size())
    throw LoadError("index accessor " + std::to_string(accessorIndex) + " has a count, offset or stride out of range");
  size_t start = view.byteOffset + a.byteOffset;
  if (a.count > 0) {
    size_t end = start + (a.count - 1) * stride + size;
    if (end > view.byteOffset + view.byteLength || end > buffer.data.size())
      throw LoadError("index accessor " + std::to_string(accessorIndex) + " reads past the end of buffer " +
                      std::to_string(view.buffer) + " (truncated file?)");
  }
  std::vector<uint32_t> out(a.count);
  for (size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = buffer.data.data() + start + i * stride;
    if (size == 1) out[i] = p[0];
    else if (size == 2) {
      uint16_t x;
      std::memcpy(&x, p, 2);
      out[i] = x;
    } else std::memcpy(&out[i], p, 4);
  }
  return out;
}

glm::mat4 nodeMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::dmat4 d = glm::make_mat4(n.matrix.data());  // column-major, as glTF
    return glm::mat4(d);
  }
  glm::mat4 t(1.0f), r(1.0f), sc(1.0f);
  if (n.translation.size() == 3)
    t = glm::translate(glm::mat4(1.0f), glm::vec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4)  // glTF: x, y, z, w
    r = glm::mat4_cast(glm::quat(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                                 static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2])));
  if (n.scale.size() == 3) sc = glm::scale(glm::mat4(1.0f), glm::vec3(n.scale[0], n.scale[1], n.scale[2]));
  return t * r * sc;
}

class GltfBuilder {
 public:
  GltfBuilder(const tinygltf::Model& m, Scene& s) : m_(m), s_(s) {}

  void build() {
    for (size_t i = 0; i < m_.materials.size(); ++i) s_.materials.push_back(material(m_.materials[i], i));
    defaultMaterial_ = static_cast<int>(s_.materials.size());
    s_.materials.push_back({"default", glm::vec3(0.8f), kDefaultSpecular, kDefaultSpecularPower, -1});
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      size_t which = m_.defaultScene >= 0 ? static_cast<size_t>(m_.defaultScene) : 0;
      roots = m_.scenes.at(which).nodes;
    } else {  // no scene: every node that is nobody's child
      std::vector<bool> child(m_.nodes.size(), false);
      for (const tinygltf::Node& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && c < static_cast<int>(child.size())) child[static_cast<size_t>(c)] = true;
      for (size_t i = 0; i < m_.nodes.size(); ++i)
        if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    for (int r : roots) visit(r, glm::mat4(1.0f), 0);
  }

 private:
  Material material(const tinygltf::Material& gm, size_t index) {
    Material mat;
    mat.name = gm.name.empty() ? "material " + std::to_string(index) : gm.name;
    const std::vector<double>& f = gm.pbrMetallicRoughness.baseColorFactor;
    if (f.size() >= 3) mat.diffuse = glm::vec3(f[0], f[1], f[2]);
    mat.specular = kDefaultSpecular;
    mat.specularPower = kDefaultSpecularPower;
    int tex = gm.pbrMetallicRoughness.baseColorTexture.index;
    if (tex >= 0) mat.diffuseTexture = texture(tex);
    // Tangent-space, +y up: the convention the shaders use (normal_mapping.glsl). The scale
    // factor is not applied (1 in the sample models).
    if (gm.normalTexture.index >= 0) mat.normalTexture = texture(gm.normalTexture.index);
    return mat;
  }

  int texture(int textureIndex) {
    auto found = textures_.find(textureIndex);
    if (found != textures_.end()) return found->second;
    if (textureIndex >= static_cast<int>(m_.textures.size()))
      throw LoadError("texture " + std::to_string(textureIndex) + " does not exist");
    int source = m_.textures[static_cast<size_t>(textureIndex)].source;
    if (source < 0 || source >= static_cast<int>(m_.images.size()))
      throw LoadError("texture " + std::to_string(textureIndex) + " has no image");
    const tinygltf::Image& img = m_.images[static_cast<size_t>(source)];
    std::string name = img.uri.empty() ? (img.name.empty() ? "image " + std::to_string(source) : img.name) : img.uri;
    if (img.image.empty() || img.width <= 0 || img.height <= 0)
      throw LoadError("image '" + name + "' is missing or cannot be decoded");
    Texture t;
    t.name = name;
    t.width = static_cast<uint32_t>(img.width);
    t.height = static_cast<uint32_t>(img.height);
    size_t texels = static_cast<size_t>(t.width) * t.height;
    if (img.component != 4 || img.bits != 8 || img.image.size() < texels * 4)
      throw LoadError("image '" + name + "' has an unsupported pixel layout");
    t.rgba8.assign(img.image.begin(), img.image.begin() + static_cast<long>(texels * 4));
    int index = static_cast<int>(s_.textures.size());
    s_.textures.push_back(std::move(t));
    textures_[textureIndex] = index;
    return index;
  }

  void visit(int nodeIndex, const glm::mat4& parent, int depth) {
    if (nodeIndex < 0 || nodeIndex >= static_cast<int>(m_.nodes.size()))
      throw LoadError("node " + std::to_string(nodeIndex) + " does not exist");
    if (depth > 64) throw LoadError("node hierarchy deeper than 64 (a cycle?)");
    const tinygltf::Node& node = m_.nodes[static_cast<size_t>(nodeIndex)];
    glm::mat4 world = parent * nodeMatrix(node);
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(m_.meshes.size())) throw LoadError("mesh " + std::to_string(node.mesh) + " does not exist");
      const tinygltf::Mesh& mesh = m_.meshes[static_cast<size_t>(node.mesh)];
      for (size_t p = 0; p < mesh.primitives.size(); ++p) primitive(mesh, p, world);
    }
    for (int c : node.children) visit(c, world, depth + 1);
  }

  void primitive(const tinygltf::Mesh& mesh, size_t p, const glm::mat4& world) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) return;  // points and lines: not drawn
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) return;
    std::string what = "mesh '" + mesh.name + "'";
    std::vector<float> positions = readAccessor(m_, pos->second, 3, what + " POSITION");
    size_t count = positions.size() / 3;
    std::vector<float> normals, uvs;
    auto nrm = prim.attributes.find("NORMAL");
    if (nrm != prim.attributes.end()) normals = readAccessor(m_, nrm->second, 3, what + " NORMAL");
    auto uv = prim.attributes.find("TEXCOORD_0");
    if (uv != prim.attributes.end()) uvs = readAccessor(m_, uv->second, 2, what + " TEXCOORD_0");
    if ((!normals.empty() && normals.size() != count * 3) || (!uvs.empty() && uvs.size() != count * 2))
      throw LoadError(what + ": attribute counts differ");

    std::vector<uint32_t> local;
    if (prim.indices >= 0) local = readIndices(m_, prim.indices);
    else
      for (uint32_t i = 0; i < count; ++i) local.push_back(i);
    for (uint32_t i : local)
      if (i >= count) throw LoadError(what + ": index " + std::to_string(i) + " out of range");

    if (s_.vertices.size() + count > kMaxSceneVertices)
      throw LoadError("more than " + std::to_string(kMaxSceneVertices) + " vertices");
    glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(world)));
    bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
    size_t firstVertex = s_.vertices.size();
    uint32_t base = static_cast<uint32_t>(firstVertex);
    for (size_t i = 0; i < count; ++i) {
      Vertex v{};
      v.position = glm::vec3(world * glm::vec4(positions[i * 3], positions[i * 3 + 1], positions[i * 3 + 2], 1.0f));
      if (!normals.empty()) {
        glm::vec3 n = normalMatrix * glm::vec3(normals[i * 3], normals[i * 3 + 1], normals[i * 3 + 2]);
        float len = glm::length(n);
        v.normal = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
      }
      if (!uvs.empty()) v.uv = {uvs[i * 2], uvs[i * 2 + 1]};  // glTF: v = 0 is the image's first row, as here
      s_.vertices.push_back(v);
    }
    Mesh out;
    out.name = mesh.name.empty() ? "mesh" : mesh.name;
    if (mesh.primitives.size() > 1) out.name += " #" + std::to_string(p);
    out.firstIndex = static_cast<uint32_t>(s_.indices.size());
    out.material = prim.material >= 0 && prim.material < static_cast<int>(m_.materials.size()) ? prim.material
                                                                                               : defaultMaterial_;
    for (size_t i = 0; i + 2 < local.size(); i += 3) {
      // Mirroring transforms flip the winding; keep triangles counter-clockwise from outside.
      s_.indices.push_back(base + local[i]);
      s_.indices.push_back(base + local[mirrored ? i + 2 : i + 1]);
      s_.indices.push_back(base + local[mirrored ? i + 1 : i + 2]);
    }
    if (normals.empty()) computeNormals(s_.vertices, s_.indices, firstVertex, out.firstIndex);
    finishMesh(s_, out, firstVertex);
  }

  const tinygltf::Model& m_;
  Scene& s_;
  int defaultMaterial_ = 0;
  std::map<int, int> textures_;
};

// tinygltf's file access, confined to the scene's folder. tinygltf turns a failed lookup into a
// generic "not found", so the first refusal is kept and reported instead.
struct ConfinedFs {
  fs::path root;
  std::string refused;

  static bool exists(const std::string& path, void* user) {
    auto* self = static_cast<ConfinedFs*>(user);
    try {
      std::string inside = self->inside(path);
      std::error_code ec;
      return fs::is_regular_file(inside, ec);
    } catch (const LoadError& e) {
      if (self->refused.empty()) self->refused = e.what();
      return false;
    }
  }
  static std::string expand(const std::string& path, void*) { return path; }  // never a shell expansion
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    auto* self = static_cast<ConfinedFs*>(user);
    try {
      return readBoundedFile(self->inside(path), out, err);
    } catch (const LoadError& e) {
      if (self->refused.empty()) self->refused = e.what();
      if (err) *err = e.what();
      return false;
    }
  }
  static bool write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err = "scene loading writes no files";
    return false;
  }
  // tinygltf joins the scene's folder and the URI; judge the URI part relative to the root.
  std::string inside(const std::string& joined) const {
    fs::path p(joined);
    fs::path rel = p.is_absolute() ? p.lexically_relative(root) : p;
    if (p.is_absolute() && (rel.empty() || *rel.begin() == ".."))
      throw LoadError("'" + joined + "' is outside the scene's folder (`..` or a symlink out of it)");
    return confinedPath(root, rel.string());
  }
};

// Image decoding for glTF, with the declared size checked before the decoder allocates.
bool loadGltfImage(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                   int reqHeight, const unsigned char* bytes, int size, void* user) {
  try {
    checkImageHeader(image->uri.empty() ? "image " + std::to_string(index) : image->uri, bytes,
                     size > 0 ? static_cast<size_t>(size) : 0);
  } catch (const LoadError& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, reqWidth, reqHeight, bytes, size, user);
}

void loadGltf(const std::string& path, bool binary, Scene& s) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ConfinedFs confined;
  // Loaded by its canonical path: tinygltf joins the file's folder and each URI, and the
  // confinement judges that against the same canonical folder.
  const std::string file = fs::canonical(path).string();
  confined.root = fs::path(file).parent_path();
  loader.SetFsCallbacks({&ConfinedFs::exists, &ConfinedFs::expand, &ConfinedFs::read, &ConfinedFs::write, &confined});
  loader.SetImageLoader(&loadGltfImage, nullptr);
  bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, file)
                   : loader.LoadASCIIFromFile(&model, &err, &warn, file);
  if (!confined.refused.empty()) throw LoadError(confined.refused);
  if (!ok) throw LoadError(err.empty() ? "not a valid glTF file" : firstLine(err));
  // tinygltf reports a missing image file as a warning and goes on; a scene without its
  // texture would render wrong, so it is an error here (checked when the texture is used).
  GltfBuilder(model, s).build();
}

// ---- OBJ + MTL ----

void loadObj(const std::string& path, Scene& s) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  const fs::path root = fs::canonical(path).parent_path();
  std::vector<unsigned char> bytes;
  std::string readError;
  if (!readBoundedFile(path, &bytes, &readError)) throw LoadError(readError);
  std::string objText(bytes.begin(), bytes.end());
  // Material libraries are read here rather than by tinyobjloader, so that each one is confined
  // to the scene's folder; their texts are handed over together.
  std::string mtlText;
  {
    std::istringstream lines(objText);
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream words(line);
      std::string keyword, library;
      if (!(words >> keyword) || keyword != "mtllib") continue;
      while (words >> library) {
        std::string libraryPath = confinedPath(root, library);
        std::vector<unsigned char> lib;
        // A missing library is tolerated as tinyobjloader and other viewers do: its materials
        // fall back to the default one (the shared dragon model names a dragon.mtl it does not
        // ship). Missing textures named by a present library stay errors.
        if (!fs::exists(libraryPath)) continue;
        if (!fs::is_regular_file(libraryPath) || !readBoundedFile(libraryPath, &lib, &readError))
          throw LoadError("material library '" + library + "': " + (readError.empty() ? "not a file" : readError));
        mtlText.append(lib.begin(), lib.end());
        mtlText += "\n";
      }
    }
  }
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(objText, mtlText, config))
    throw LoadError(reader.Error().empty() ? "not a valid OBJ file" : firstLine(reader.Error()));
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::vector<tinyobj::material_t>& materials = reader.GetMaterials();

  // Keyed by path and use: a file used as a bump (height) map is stored converted.
  std::map<std::pair<std::string, bool>, int> textureByPath;
  auto loadTexture = [&](const tinyobj::material_t& om, const std::string& name, bool bumpMap) {
    std::string texPath = confinedPath(root, name);
    auto found = textureByPath.find({texPath, bumpMap});
    if (found != textureByPath.end()) return found->second;
    std::vector<unsigned char> bytes;
    if (!fs::is_regular_file(texPath) || !readBoundedFile(texPath, &bytes, &readError))
      throw LoadError("material '" + om.name + "': texture '" + name + "' not found");
    Texture t = decodeTexture(name, bytes);
    if (bumpMap && isGrey(t)) t = normalMapFromHeights(t, om.bump_texopt.bump_multiplier);
    int index = static_cast<int>(s.textures.size());
    s.textures.push_back(std::move(t));
    textureByPath[{texPath, bumpMap}] = index;
    return index;
  };
  for (const tinyobj::material_t& om : materials) {
    Material mat;
    mat.name = om.name;
    mat.diffuse = glm::vec3(om.diffuse[0], om.diffuse[1], om.diffuse[2]);
    mat.specular = glm::vec3(om.specular[0], om.specular[1], om.specular[2]);
    mat.specularPower = om.shininess > 0.0f ? om.shininess : kDefaultSpecularPower;
    if (!om.diffuse_texname.empty()) mat.diffuseTexture = loadTexture(om, om.diffuse_texname, false);
    // `norm` names a tangent-space normal map; `bump` / `map_Bump` name either one (as many
    // exporters write them) or a grey height map, which is converted.
    if (!om.normal_texname.empty()) mat.normalTexture = loadTexture(om, om.normal_texname, false);
    else if (!om.bump_texname.empty()) mat.normalTexture = loadTexture(om, om.bump_texname, true);
    s.materials.push_back(mat);
  }
  const int defaultMaterial = static_cast<int>(s.materials.size());
  s.materials.push_back({"default", glm::vec3(0.8f), kDefaultSpecular, kDefaultSpecularPower, -1});

  const size_t positionCount = attrib.vertices.size() / 3;
  const size_t normalCount = attrib.normals.size() / 3;
  const size_t uvCount = attrib.texcoords.size() / 2;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
    const std::vector<int>& faceMaterial = shape.mesh.material_ids;
    // One Mesh per material used by the shape, in order of first use.
    std::vector<int> order;
    for (int mid : faceMaterial)
      if (std::find(order.begin(), order.end(), mid) == order.end()) order.push_back(mid);
    for (int mid : order) {
      size_t firstVertex = s.vertices.size();
      Mesh mesh;
      mesh.name = shape.name.empty() ? "shape" : shape.name;
      if (order.size() > 1 && mid >= 0) mesh.name += " / " + materials[static_cast<size_t>(mid)].name;
      mesh.material = mid >= 0 && mid < defaultMaterial ? mid : defaultMaterial;
      mesh.firstIndex = static_cast<uint32_t>(s.indices.size());
      std::map<std::tuple<int, int, int>, uint32_t> unique;
      bool anyMissingNormal = false;
      for (size_t f = 0; f < faceMaterial.size(); ++f) {
        if (faceMaterial[f] != mid) continue;
        for (size_t k = 0; k < 3; ++k) {
          const tinyobj::index_t& ix = idx.at(f * 3 + k);
          if (ix.vertex_index < 0 || static_cast<size_t>(ix.vertex_index) >= positionCount)
            throw LoadError("face " + std::to_string(f + 1) + " of '" + mesh.name + "' names a missing vertex");
          int n = ix.normal_index >= 0 && static_cast<size_t>(ix.normal_index) < normalCount ? ix.normal_index : -1;
          int t = ix.texcoord_index >= 0 && static_cast<size_t>(ix.texcoord_index) < uvCount ? ix.texcoord_index : -1;
          auto key = std::make_tuple(ix.vertex_index, n, t);
          auto found = unique.find(key);
          if (found != unique.end()) {
            s.indices.push_back(found->second);
            continue;
          }
          Vertex v{};
          size_t vi = static_cast<size_t>(ix.vertex_index);
          v.position = {attrib.vertices[vi * 3], attrib.vertices[vi * 3 + 1], attrib.vertices[vi * 3 + 2]};
          if (n >= 0) {
            size_t ni = static_cast<size_t>(n);
            v.normal = glm::vec3(attrib.normals[ni * 3], attrib.normals[ni * 3 + 1], attrib.normals[ni * 3 + 2]);
            float len = glm::length(v.normal);
            v.normal = len > 0.0f ? v.normal / len : glm::vec3(0.0f, 1.0f, 0.0f);
          } else {
            anyMissingNormal = true;
          }
          if (t >= 0) {  // OBJ: v = 0 is the image's bottom row; here v = 0 is row 0 (the top)
            size_t ti = static_cast<size_t>(t);
            v.uv = {attrib.texcoords[ti * 2], 1.0f - attrib.texcoords[ti * 2 + 1]};
          }
          if (s.vertices.size() >= kMaxSceneVertices)
            throw LoadError("more than " + std::to_string(kMaxSceneVertices) + " vertices");
          uint32_t index = static_cast<uint32_t>(s.vertices.size());
          unique.emplace(key, index);
          s.vertices.push_back(v);
          s.indices.push_back(index);
        }
      }
      if (anyMissingNormal) computeNormals(s.vertices, s.indices, firstVertex, mesh.firstIndex);
      finishMesh(s, mesh, firstVertex);
    }
  }
}

// Cameras around the bounds: "default" (and "outside", the same view) in front and above,
// "high", "side", "close", and "inside" at the centre looking along the longer horizontal axis
// (for interiors such as Sponza, whose "default" becomes that view: loadSceneFile).
std::vector<Camera> camerasFor(glm::vec3 lo, glm::vec3 hi) {
  glm::vec3 c = 0.5f * (lo + hi);
  float r = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  auto at = [&](const char* name, glm::vec3 dir, float distance) {
    Camera cam;
    cam.name = name;
    cam.position = c + glm::normalize(dir) * distance;
    cam.target = c;
    cam.nearPlane = r * 0.01f;
    cam.farPlane = r * 10.0f;
    return cam;
  };
  std::vector<Camera> cams = {
      at("default", {0.0f, 0.35f, 1.0f}, 2.1f * r),
      at("outside", {0.0f, 0.35f, 1.0f}, 2.1f * r),  // the default's view, kept when "default" moves inside
      at("high", {0.6f, 1.2f, 0.9f}, 2.1f * r),
      at("side", {1.0f, 0.25f, 0.2f}, 2.1f * r),
      at("close", {0.25f, 0.3f, 1.0f}, 1.2f * r),
  };
  Camera inside;
  inside.name = "inside";
  glm::vec3 axis = (hi.x - lo.x) >= (hi.z - lo.z) ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  float half = 0.5f * glm::dot(hi - lo, axis);
  inside.position = c + axis * (0.8f * half) - glm::vec3(0.0f, 0.25f * (hi.y - lo.y), 0.0f);
  inside.target = c - axis * half;
  inside.nearPlane = r * 0.005f;
  inside.farPlane = r * 10.0f;
  cams.push_back(inside);
  return cams;
}

}  // namespace

bool loadSceneFile(const std::string& path, const SceneParams& params, Scene* out, std::string* error) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    *error = path + ": file not found";
    return false;
  }
  Scene s;
  s.name = fs::path(path).stem().string();
  try {
    if (ext == ".gltf" || ext == ".glb") loadGltf(path, ext == ".glb", s);
    else if (ext == ".obj") loadObj(path, s);
    else throw LoadError("unknown scene file type '" + ext + "' (expected .gltf, .glb or .obj)");
  } catch (const LoadError& e) {
    *error = path + ": " + e.what();
    return false;
  } catch (const std::exception& e) {  // e.g. std::out_of_range from a malformed index
    *error = path + ": malformed file (" + e.what() + ")";
    return false;
  }
  if (s.meshes.empty()) {
    *error = path + ": no triangles";
    return false;
  }
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const Mesh& m : s.meshes) {
    lo = glm::min(lo, m.boundsMin);
    hi = glm::max(hi, m.boundsMax);
  }
  for (float v : {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z})
    if (!std::isfinite(v)) {
      *error = path + ": vertex positions are not finite";
      return false;
    }
  s.cameras = camerasFor(lo, hi);
  // An enclosed model (an interior such as Sponza) seen from around its bounds shows only its
  // outer walls: its default camera is then the one inside, and the bounds view is "outside".
  if (enclosure(s, s.cameras.back().position) >= 0.9f) {
    s.cameras.front() = s.cameras.back();
    s.cameras.front().name = "default";
  }
  s.directionalDir = {-0.3f, -1.0f, -0.4f};
  placeLights(s, params, s.cameras[0], lo, hi);
  *out = std::move(s);
  return true;
}

}  // namespace parity::scene
