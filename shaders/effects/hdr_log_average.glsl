// Where the bright and tone-mapping passes read the log-average luminance: the compute
// reduction's result buffer, or, on a device without compute shaders, texel 0 of the pixel
// chain's result level (HDR_LUMINANCE_TEXTURE; techniques/hdr/luminance.h).
#ifndef PARITY_HDR_LOG_AVERAGE_GLSL
#define PARITY_HDR_LOG_AVERAGE_GLSL

#ifdef HDR_LUMINANCE_TEXTURE
layout(set = 0, binding = 9) uniform sampler2D luminanceResult;
float logAverageLuminance() { return texelFetch(luminanceResult, ivec2(0, 0), 0).r; }
#else
layout(set = 0, binding = 9, std430) readonly buffer Result { vec4 result; };  // x: log-average
float logAverageLuminance() { return result.x; }
#endif

#endif
