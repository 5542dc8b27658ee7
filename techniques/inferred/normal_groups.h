// Normal-group IDs of inferred lighting (Kircher & Lawrance 2009, §3.1): faces of a mesh that
// are connected across edges with continuous normals share an ID, so the discontinuity
// sensitive filter can tell a crease from a smooth surface without reconstructing normals.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace parity::techniques::inferred {

// One ID per triangle of `mesh` (index range order). The dual graph of the mesh (a node per
// triangle, an arc per edge two triangles share) keeps an arc only when both triangles carry the
// same normals at both vertices of the edge; each connected component k (numbered in the order
// of its first triangle) gets the ID (167 k + 89) mod 256 (8 bits in the DSF buffer): spread like
// the paper's random IDs, but a permutation, so components differ unless a mesh has more than
// 256 of them.
// Edges are matched by vertex position (quantised to 1e-5 of the mesh's extent), not by index,
// because meshes duplicate vertices along creases and UV seams.
std::vector<uint8_t> normalGroups(const scene::Scene& scene, const scene::Mesh& mesh);

// The number of distinct components before the modulo (for tests and `--passes` reports).
uint32_t normalGroupCount(const scene::Scene& scene, const scene::Mesh& mesh);

}  // namespace parity::techniques::inferred
