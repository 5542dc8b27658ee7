// Tiled light culling on the CPU: the path a port takes where the device has no compute shaders
// (ps3 and x360, where the SPUs or the CPU build the lists; dx10, where compute is optional).
// Each 16x16 tile's frustum, widened by a pixel on every side (D3D9 pixel centres move the
// surface half a pixel), is tested against every light's sphere (a spot's cone lies inside it).
// The lists differ from the compute pass's (light_cull.comp bounds the tile by the box of its
// surface points: tighter in depth, looser at the box's corners) but, in the same scene order,
// each holds every light that reaches a pixel of its tile, and the shading adds nothing for a
// light that reaches none: the images are the compute path's bit for bit
// (tests/technique_tiled_test.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace parity::techniques {

// The tile list buffer as light_cull.comp writes it (tile_lists.glsl): for tile t, row by row,
// at t * stride its light count, then that many light indices in ascending order.
std::vector<uint32_t> cullLightsPerTile(const std::vector<scene::Light>& lights, const glm::mat4& viewProj,
                                        uint32_t width, uint32_t height, uint32_t tileSize, uint32_t stride);

}  // namespace parity::techniques
