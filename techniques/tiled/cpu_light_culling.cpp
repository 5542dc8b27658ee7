#include "techniques/tiled/cpu_light_culling.h"

#include <algorithm>

#include "scene/culling.h"

namespace parity::techniques {

std::vector<uint32_t> cullLightsPerTile(const std::vector<scene::Light>& lights, const glm::mat4& viewProj,
                                        uint32_t width, uint32_t height, uint32_t tileSize, uint32_t stride) {
  const uint32_t tilesX = (width + tileSize - 1) / tileSize, tilesY = (height + tileSize - 1) / tileSize;
  std::vector<uint32_t> words(size_t(tilesX) * tilesY * stride, 0u);
  for (uint32_t ty = 0; ty < tilesY; ++ty)
    for (uint32_t tx = 0; tx < tilesX; ++tx) {
      // The tile in NDC (pixel y down, as the culling and shading passes map pixels), one pixel wider.
      const float x0 = (float(tx * tileSize) - 1.0f) / float(width) * 2.0f - 1.0f;
      const float x1 = (float(std::min((tx + 1) * tileSize, width)) + 1.0f) / float(width) * 2.0f - 1.0f;
      const float y0 = (float(ty * tileSize) - 1.0f) / float(height) * 2.0f - 1.0f;
      const float y1 = (float(std::min((ty + 1) * tileSize, height)) + 1.0f) / float(height) * 2.0f - 1.0f;
      // Clip space cropped to the tile: x' = sx (x - cx w), y' likewise.
      const float sx = 2.0f / (x1 - x0), sy = 2.0f / (y1 - y0), cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
      glm::mat4 crop(1.0f);
      crop[0][0] = sx;
      crop[3][0] = -sx * cx;
      crop[1][1] = sy;
      crop[3][1] = -sy * cy;
      const scene::Frustum f = scene::frustumFromViewProjection(crop * viewProj);
      uint32_t* entry = words.data() + (size_t(ty) * tilesX + tx) * stride;
      uint32_t count = 0;
      for (uint32_t i = 0; i < lights.size() && count + 1 < stride; ++i) {
        bool outside = false;
        for (const glm::vec4& p : f.planes) {
          const glm::vec3 n(p);
          // Conservative: rejected only when the sphere lies clearly outside one plane.
          if (glm::dot(n, lights[i].position) + p.w < -lights[i].radius * glm::length(n) * 1.001f - 1e-4f) {
            outside = true;
            break;
          }
        }
        if (!outside) entry[1 + count++] = i;
      }
      entry[0] = count;
    }
  return words;
}

}  // namespace parity::techniques
