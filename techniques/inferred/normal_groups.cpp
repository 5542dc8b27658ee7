#include "techniques/inferred/normal_groups.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace parity::techniques::inferred {

namespace {

using PositionKey = std::array<int64_t, 3>;

struct Components {
  std::vector<uint32_t> componentOfFace;  // dense, in order of each component's first face
  uint32_t count = 0;
};

Components findComponents(const scene::Scene& s, const scene::Mesh& mesh) {
  const uint32_t faceCount = mesh.indexCount / 3;
  std::vector<uint32_t> parent(faceCount);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };

  glm::vec3 extent = mesh.boundsMax - mesh.boundsMin;
  float quantum = std::max({extent.x, extent.y, extent.z, 1e-6f}) * 1e-5f;
  auto key = [&](uint32_t vertex) {
    glm::vec3 p = s.vertices[vertex].position;
    return PositionKey{std::llround(p.x / quantum), std::llround(p.y / quantum), std::llround(p.z / quantum)};
  };
  auto sameNormal = [&](uint32_t a, uint32_t b) {
    glm::vec3 d = s.vertices[a].normal - s.vertices[b].normal;
    return glm::dot(d, d) < 1e-8f;
  };

  // Edge (ordered pair of position keys) -> the (face, vertex at the smaller key, vertex at the
  // larger key) of every triangle that has it.
  std::map<std::pair<PositionKey, PositionKey>, std::vector<std::array<uint32_t, 3>>> edges;
  for (uint32_t f = 0; f < faceCount; ++f) {
    const uint32_t* tri = &s.indices[mesh.firstIndex + 3 * f];
    for (int e = 0; e < 3; ++e) {
      uint32_t va = tri[e], vb = tri[(e + 1) % 3];
      PositionKey ka = key(va), kb = key(vb);
      if (ka == kb) continue;  // degenerate edge (sphere poles)
      if (kb < ka) {
        std::swap(ka, kb);
        std::swap(va, vb);
      }
      edges[{ka, kb}].push_back({f, va, vb});
    }
  }
  for (const auto& [edge, uses] : edges)
    for (size_t i = 0; i < uses.size(); ++i)
      for (size_t j = i + 1; j < uses.size(); ++j)
        if (sameNormal(uses[i][1], uses[j][1]) && sameNormal(uses[i][2], uses[j][2]))
          parent[find(uses[i][0])] = find(uses[j][0]);

  Components c;
  c.componentOfFace.resize(faceCount);
  std::map<uint32_t, uint32_t> dense;
  for (uint32_t f = 0; f < faceCount; ++f) {
    auto [it, inserted] = dense.emplace(find(f), c.count);
    if (inserted) ++c.count;
    c.componentOfFace[f] = it->second;
  }
  return c;
}

}  // namespace

std::vector<uint8_t> normalGroups(const scene::Scene& s, const scene::Mesh& mesh) {
  Components c = findComponents(s, mesh);
  std::vector<uint8_t> ids(c.componentOfFace.size());
  // Component k gets (167 k + 89) mod 256: a permutation of 0..255 (167 is odd), so the first 256
  // components stay distinct, while the values are spread over all 8 bits as the paper's random
  // IDs are (a value path that keeps only the upper bits of the DSF channel then loses them, as
  // it would on hardware, instead of happening to keep a run of small IDs).
  for (size_t f = 0; f < ids.size(); ++f) ids[f] = static_cast<uint8_t>((c.componentOfFace[f] * 167u + 89u) & 255u);
  return ids;
}

uint32_t normalGroupCount(const scene::Scene& s, const scene::Mesh& mesh) { return findComponents(s, mesh).count; }

}  // namespace parity::techniques::inferred
