#version 450
// Depth-peeling composite: the peeled layers (nearest first) blended back to front over the
// opaque image; a layer no fragment reached holds opacity 0.
#include "platform.glsl"
layout(set = 0, binding = 4) uniform sampler2D layer0;
layout(set = 0, binding = 5) uniform sampler2D layer1;
layout(set = 0, binding = 6) uniform sampler2D layer2;
layout(set = 0, binding = 7) uniform sampler2D layer3;
layout(set = 0, binding = 8) uniform sampler2D opaqueImage;  // the platform's Rgba16Hdr read texture

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 l[4] = vec4[](parityReadRgba16Hdr(texelFetch(layer0, p, 0)), parityReadRgba16Hdr(texelFetch(layer1, p, 0)),
                     parityReadRgba16Hdr(texelFetch(layer2, p, 0)), parityReadRgba16Hdr(texelFetch(layer3, p, 0)));
  vec3 result = parityReadRgba16Hdr(texelFetch(opaqueImage, p, 0)).rgb;
  for (int i = 3; i >= 0; --i) result = mix(result, l[i].rgb, l[i].a);
  outColor = vec4(result, 1.0);
}
