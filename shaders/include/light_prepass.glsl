// Light accumulation of deferred lighting / light pre-pass (RTR blog "Deferred lighting
// approaches"): diffuse and specular light are summed separately so that a second geometry pass
// can apply the materials' colours.
//   6 channels (default): two Rgba16Hdr targets, diffuse RGB and specular RGB.
//   4 channels (PARITY_LIGHT_PREPASS_4CH): one Rgba16Hdr target, diffuse RGB and the specular
//   light's luminance in A; the specular colour is reconstructed from the diffuse light's
//   chromaticity (appendix A): specular = diffuse / (lum(diffuse) + eps) * A. Exact for one
//   light; with several lights of different colours every highlight takes the mixed hue.
// Needs the platform layer (parityWriteRgba16Hdr / parityReadRgba16Hdr) included before.
#ifndef PARITY_LIGHT_PREPASS_GLSL
#define PARITY_LIGHT_PREPASS_GLSL

#ifndef PARITY_LIGHT_PREPASS_4CH
#define PARITY_LIGHT_PREPASS_4CH 0
#endif

// Luminance of linear RGB with the primaries of standard monitors and televisions (Rec. 709).
float luminance(vec3 c) { return (0.2126 * c.r + 0.7152 * c.g) + 0.0722 * c.b; }

// Keeps the division finite where no diffuse light arrived (there is no specular light there
// either: S is 0 wherever D is, eq. 3.10).
const float kChromaticityEpsilon = 1e-6;

#ifdef PARITY_LIGHT_ACCUMULATION_OUTPUTS
#if PARITY_LIGHT_PREPASS_4CH
layout(location = 0) out vec4 outLight;
void writeLight(vec3 diffuseLight, vec3 specularLight) {
  outLight = parityWriteRgba16Hdr(vec4(diffuseLight, luminance(specularLight)));
}
#else
layout(location = 0) out vec4 outDiffuseLight;
layout(location = 1) out vec4 outSpecularLight;
void writeLight(vec3 diffuseLight, vec3 specularLight) {
  outDiffuseLight = parityWriteRgba16Hdr(vec4(diffuseLight, 0.0));
  outSpecularLight = parityWriteRgba16Hdr(vec4(specularLight, 0.0));
}
#endif
#endif

// The accumulated light at this pixel (second geometry pass): diffuse and specular light.
#ifdef PARITY_LIGHT_ACCUMULATION_INPUTS
layout(set = 0, binding = 8) uniform sampler2D lightDiffuse;  // 4 channels: diffuse RGB + specular luminance
#if !PARITY_LIGHT_PREPASS_4CH
layout(set = 0, binding = 9) uniform sampler2D lightSpecular;
#endif
void readLight(out vec3 diffuseLight, out vec3 specularLight) {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 d = parityReadRgba16Hdr(texelFetch(lightDiffuse, p, 0));
  diffuseLight = d.rgb;
#if PARITY_LIGHT_PREPASS_4CH
  specularLight = d.rgb / (luminance(d.rgb) + kChromaticityEpsilon) * d.a;
#else
  specularLight = parityReadRgba16Hdr(texelFetch(lightSpecular, p, 0)).rgb;
#endif
}
#endif

#endif
