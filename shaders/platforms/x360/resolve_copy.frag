#version 450
// Xbox 360 resolve of a rectangle of a one-sample surface whose format the resolve does not
// convert (k_8_8_8_8, k_32_FLOAT, k_2_10_10_10_FLOAT): the texels themselves. The pass's viewport
// is the rectangle (GpuTargets::resolve with a rect); a whole surface is a copyTexture instead.
layout(binding = 0) uniform sampler2D uEdram;
layout(location = 0) out vec4 oColor;
void main() { oColor = texelFetch(uEdram, ivec2(gl_FragCoord.xy), 0); }
