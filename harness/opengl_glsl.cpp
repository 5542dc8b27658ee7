#include "harness/opengl_glsl.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <regex>

namespace parity::harness::script {

namespace {

// The GLSL version in which each extension became core (OpenGL 4.5 core profile, appendix of
// each version's GLSL specification).
int coreVersion(const std::string& extension) {
  static const std::map<std::string, int> kCore = {
      {"GL_ARB_texture_rectangle", 140},         {"GL_ARB_uniform_buffer_object", 140},
      {"GL_ARB_explicit_attrib_location", 330},  {"GL_ARB_shader_bit_encoding", 330},
      {"GL_ARB_gpu_shader5", 400},               {"GL_ARB_gpu_shader_fp64", 400},
      {"GL_ARB_tessellation_shader", 400},       {"GL_ARB_texture_query_lod", 400},
      {"GL_ARB_sample_shading", 400},            {"GL_ARB_texture_cube_map_array", 400},
      {"GL_ARB_texture_gather", 400},            {"GL_ARB_shader_subroutine", 400},
      {"GL_ARB_separate_shader_objects", 410},   {"GL_ARB_vertex_attrib_64bit", 410},
      {"GL_ARB_viewport_array", 410},            {"GL_ARB_shading_language_420pack", 420},
      {"GL_ARB_shader_atomic_counters", 420},    {"GL_ARB_shader_image_load_store", 420},
      {"GL_ARB_conservative_depth", 420},        {"GL_ARB_shading_language_packing", 420},
      {"GL_ARB_arrays_of_arrays", 430},          {"GL_ARB_compute_shader", 430},
      {"GL_ARB_shader_storage_buffer_object", 430}, {"GL_ARB_explicit_uniform_location", 430},
      {"GL_ARB_fragment_layer_viewport", 430},   {"GL_ARB_shader_image_size", 430},
      {"GL_ARB_texture_query_levels", 430},      {"GL_ARB_enhanced_layouts", 440},
      {"GL_ARB_cull_distance", 450},             {"GL_ARB_derivative_control", 450},
      {"GL_ARB_shader_texture_image_samples", 450}};
  auto it = kCore.find(extension);
  return it == kCore.end() ? 0 : it->second;
}

std::string replaceWord(const std::string& text, const std::string& word, const std::string& with) {
  return std::regex_replace(text, std::regex("\\b" + word + "\\b"), with);
}

// Joins lines ending in a backslash (a continuation GLSL only allows from 4.20, which Mesa and so
// piglit's shaders use in every version), keeping the line count: the removed line breaks
// follow the joined line.
std::string joinContinuedLines(const std::string& text) {
  std::string out;
  int pending = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\' && i + 1 < text.size() && text[i + 1] == '\n') {
      ++pending;
      ++i;
      continue;
    }
    out += text[i];
    if (text[i] == '\n') out.append(static_cast<size_t>(pending), '\n'), pending = 0;
  }
  return out;
}

}  // namespace

OpenGlGlsl prepareOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion) {
  OpenGlGlsl out;
  out.source = joinContinuedLines(source);
  int version = defaultVersion;
  size_t v = source.find("#version");
  size_t number = v == std::string::npos ? v : source.find_first_of("0123456789", v);
  size_t numberEnd = number == std::string::npos ? number : source.find_first_not_of("0123456789", number);
  if (number != std::string::npos) version = std::stoi(source.substr(number, numberEnd - number));
  int target = std::max(version, 140);
  static const std::regex kExtension(R"(#\s*extension\s+(GL_\w+))");
  for (auto it = std::sregex_iterator(source.begin(), source.end(), kExtension); it != std::sregex_iterator(); ++it)
    target = std::max(target, coreVersion((*it)[1]));
  // An #extension directive for what the raised version has as core is dropped (line kept
  // empty): glslang's SPIR-V path does not know the GL_ARB names and refuses `require`.
  {
    static const std::regex kDirective(R"(#[ \t]*extension[ \t]+(GL_\w+)[ \t]*:[ \t]*\w+)");
    std::string kept;
    size_t from = 0;
    for (auto it = std::sregex_iterator(out.source.begin(), out.source.end(), kDirective); it != std::sregex_iterator(); ++it) {
      const int core = coreVersion((*it)[1]);
      if (core == 0 || core > target) continue;
      kept += out.source.substr(from, static_cast<size_t>(it->position()) - from);
      from = static_cast<size_t>(it->position() + it->length());
    }
    out.source = kept + out.source.substr(from);
  }
  if (stage == Stage::Vertex && version < 140 && std::regex_search(out.source, std::regex("\\bgl_Vertex\\b"))) {
    // GLSL before 1.40 reads the position as gl_Vertex, which is generic attribute 0.
    out.source = replaceWord(out.source, "gl_Vertex", "parity_Vertex");
    out.declarations += "in vec4 parity_Vertex;\n";
  }
  if (target >= 420) {
    // Removed from the core profile in 4.20: the 1.x interface qualifiers and outputs.
    std::string& s = out.source;
    s = replaceWord(s, "attribute", "in");
    s = replaceWord(s, "varying", stage == Stage::Vertex ? "out" : "in");
    if (stage == Stage::Fragment && std::regex_search(s, std::regex("\\bgl_FragColor\\b"))) {
      s = replaceWord(s, "gl_FragColor", "parity_FragColor");
      out.declarations += "layout(location = 0) out vec4 parity_FragColor;\n";
    }
    if (stage == Stage::Fragment && std::regex_search(s, std::regex("\\bgl_FragData\\b"))) {
      s = replaceWord(s, "gl_FragData", "parity_FragData");
      out.declarations += "layout(location = 0) out vec4 parity_FragData[4];\n";
    }
  }
  std::string line = "#version " + std::to_string(target);
  if (v == std::string::npos) {
    out.source = line + "\n" + out.source;
  } else {
    size_t eol = out.source.find('\n', out.source.find("#version"));
    size_t at = out.source.find("#version");
    out.source.replace(at, (eol == std::string::npos ? out.source.size() : eol) - at, line);
  }
  return out;
}

}  // namespace parity::harness::script
