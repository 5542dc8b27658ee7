// GL context providers: where the backend's OpenGL 4.5 core context comes from. Both render
// only to framebuffer objects; neither has a window.
//  * "egl":    EGL on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless), no surface.
//  * "osmesa": Mesa's off-screen interface, made current on a small dummy colour buffer.
#pragma once

#include <memory>
#include <string>

namespace parity::rhi::gl {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual const char* providerName() const = 0;  // "egl" or "osmesa"
  // Address of a GL entry point ("glDrawArrays"), or null.
  virtual void* getProcAddress(const char* name) = 0;
  virtual bool makeCurrent() = 0;
};

// Creates a 4.5 core-profile context (`compatibility`: a 4.5 compatibility-profile one) and makes
// it current on the calling thread. On failure returns null with a one-line reason ("EGL:
// eglInitialize failed (EGL_NOT_INITIALIZED)"). `debug` asks for a debug context where the
// provider can express it.
std::unique_ptr<GlContext> createGlContext(const std::string& provider, bool debug, bool compatibility, std::string* whyNot);

}  // namespace parity::rhi::gl
