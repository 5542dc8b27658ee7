#version 450
// The lit image times the blurred occlusion, upsampled bilinearly from its reduced resolution.
layout(set = 0, binding = 6) uniform sampler2D occlusion;
layout(set = 0, binding = 7) uniform sampler2D litImage;

layout(location = 0) out vec4 outColor;

void main() {
  vec2 uv = gl_FragCoord.xy / vec2(textureSize(litImage, 0));
  float ao = texture(occlusion, uv).r;
  vec3 lit = texelFetch(litImage, ivec2(gl_FragCoord.xy), 0).rgb;
  outColor = vec4(lit * ao, 1.0);
}
