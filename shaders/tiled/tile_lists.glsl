// Per-tile light lists (16 x 16 pixel tiles) built by light_cull.comp, read by the tiled deferred
// and tiled forward shaders. Tile t's entry starts at t * params.x: its light count, then that
// many scene light indices in ascending order (the forward shader's summation order).
#ifndef PARITY_TILE_LISTS_GLSL
#define PARITY_TILE_LISTS_GLSL

#define TILE_SIZE 16

layout(set = 0, binding = 9, std140) uniform TileParams {
  uvec4 params;  // x: entry stride in uints (max lights per tile + 1), y: tiles across, z: tiles down
} tiles;

uint tileEntry(ivec2 pixel) {
  uvec2 tile = uvec2(pixel) / uint(TILE_SIZE);
  return (tile.y * tiles.params.y + tile.x) * tiles.params.x;
}

#endif
