#include "rhi/gl/gl_functions.h"

namespace parity::rhi::gl {

bool loadGlFunctions(GlFunctions* gl, GlGetProcAddress getProc, void* userData, std::string* missing) {
  missing->clear();
#define PARITY_GL_LOAD(type, name)                                          \
  gl->name = reinterpret_cast<type>(getProc("gl" #name, userData));         \
  if (!gl->name) missing->append(missing->empty() ? "gl" #name : " gl" #name);
  PARITY_GL_FUNCTIONS(PARITY_GL_LOAD)
#undef PARITY_GL_LOAD
  return missing->empty();
}

}  // namespace parity::rhi::gl
