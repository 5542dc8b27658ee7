#version 450
// The log-average's reduction as pixel passes: the path a port takes where the device has no
// compute shaders (techniques/hdr/luminance.h; hdr_luminance.comp is the other). Every pass adds
// pairs of texels of the level above in exactly the order the compute tree adds them, so both
// paths give the same float, bit for bit. By mode:
//  0: log(delta + L) of two pixels of a 16x16 block of the HDR image (pixels outside it add 0)
//  1: two texels of the level above, `block.zw` apart within blocks of `block.xy` texels
//  2: texel i sums the blocks' partial sums i, i + 256, ... from 0, as the compute path's
//     second dispatch loads them
//  3: the result as the compute path's buffer holds it: texel 0 the log-average, 1 the mean log,
//     2 the pixels counted, 3 zero
#include "parity_math.glsl"
#include "platform.glsl"  // source is the platform's Rgba16Hdr read texture in mode 0

layout(set = 0, binding = 4) uniform sampler2D source;

layout(push_constant, std430) uniform Chain {
  ivec4 block;   // modes 0, 1: xy the block size in the source, zw the offset of the texel added; mode 2: x the blocks across
  ivec4 image;   // xy: the HDR image size, z: the partial sums (blocks), w: the mode
  vec4 params;   // x: delta
} chain;

layout(location = 0) out vec4 outValue;

float luminance(vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

float logLuminance(ivec2 p) {
  if (any(greaterThanEqual(p, chain.image.xy))) return 0.0;
  return log(chain.params.x + max(luminance(parityReadRgba16Hdr(texelFetch(source, p, 0)).rgb), 0.0));
}

float level(ivec2 p) { return texelFetch(source, p, 0).r; }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int mode = chain.image.w;
  float v = 0.0;
  if (mode <= 1) {
    ivec2 folded = chain.block.xy - chain.block.zw;
    ivec2 first = (p / folded) * chain.block.xy + p % folded;
    ivec2 second = first + chain.block.zw;
    v = mode == 0 ? logLuminance(first) + logLuminance(second) : level(first) + level(second);
  } else if (mode == 2) {
    for (int i = p.x; i < chain.image.z; i += 256) v += level(ivec2(i % chain.block.x, i / chain.block.x));
  } else {
    float count = float(uint(chain.image.x) * uint(chain.image.y));
    float meanLog = level(ivec2(0, 0)) / count;
    v = p.x == 0 ? exp(meanLog) : p.x == 1 ? meanLog : p.x == 2 ? count : 0.0;
  }
  outValue = vec4(v, 0.0, 0.0, 0.0);
}
