#include "rhi/gl/gl_context.h"

// No X11 types from eglplatform.h: the surfaceless platform needs no native display.
#define EGL_NO_X11
#define MESA_EGL_NO_X11_HEADERS
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstring>
#include <map>
#include <vector>

namespace parity::rhi::gl {

namespace {

// ---------------------------------------------------------------------------------------------
// EGL, surfaceless platform
// ---------------------------------------------------------------------------------------------
const char* eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
  }
}

std::string eglFailure(const char* what) {
  return std::string("EGL: ") + what + " failed (" + eglErrorName(eglGetError()) + ")";
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool startOk = p == list || p[-1] == ' ';
    const bool endOk = p[n] == '\0' || p[n] == ' ';
    if (startOk && endOk) return true;
  }
  return false;
}

// eglTerminate is per display and not reference counted, so count our contexts on each display
// and terminate it only when the last one goes.
std::map<EGLDisplay, int>& liveContextsPerDisplay() {
  static std::map<EGLDisplay, int> counts;
  return counts;
}

class EglContext final : public GlContext {
 public:
  EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {
    ++liveContextsPerDisplay()[display_];
  }
  ~EglContext() override {
    if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    if (--liveContextsPerDisplay()[display_] == 0) {
      liveContextsPerDisplay().erase(display_);
      eglTerminate(display_);
      eglReleaseThread();
    }
  }
  const char* providerName() const override { return "egl"; }
  void* getProcAddress(const char* name) override { return reinterpret_cast<void*>(eglGetProcAddress(name)); }
  bool makeCurrent() override {
    return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
  }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

std::unique_ptr<GlContext> createEgl(bool debug, bool compatibility, std::string* whyNot) {
  // Client extensions (display-independent). Without a driver libglvnd still answers, but
  // without the Mesa platform string.
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    *whyNot = "EGL: no surfaceless platform (EGL_MESA_platform_surfaceless missing)";
    return nullptr;
  }
  if (!hasExtension(clientExtensions, "EGL_EXT_platform_base")) {
    *whyNot = "EGL: no platform displays (EGL_EXT_platform_base missing)";
    return nullptr;
  }
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) {
    *whyNot = "EGL: eglGetPlatformDisplayEXT not found";
    return nullptr;
  }
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) {
    *whyNot = eglFailure("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
    return nullptr;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    *whyNot = eglFailure("eglInitialize");
    return nullptr;
  }
  // From here on a failure must terminate the display unless another context of ours uses it.
  auto fail = [&](std::string reason) -> std::unique_ptr<GlContext> {
    *whyNot = std::move(reason);
    if (liveContextsPerDisplay().count(display) == 0) eglTerminate(display);
    return nullptr;
  };
  if (!eglBindAPI(EGL_OPENGL_API)) return fail(eglFailure("eglBindAPI(EGL_OPENGL_API)"));

  const char* displayExtensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(displayExtensions, "EGL_KHR_create_context") && (major < 1 || (major == 1 && minor < 5)))
    return fail("EGL: cannot request a core-profile context (EGL_KHR_create_context missing)");
  if (!hasExtension(displayExtensions, "EGL_KHR_surfaceless_context"))
    return fail("EGL: contexts without a surface are not supported (EGL_KHR_surfaceless_context missing)");

  EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
  if (!hasExtension(displayExtensions, "EGL_KHR_no_config_context")) {
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count == 0)
      return fail("EGL: no config renders OpenGL");
  }

  std::vector<EGLint> attribs = {EGL_CONTEXT_MAJOR_VERSION_KHR, 4,
                                 EGL_CONTEXT_MINOR_VERSION_KHR, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
                                 compatibility ? EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT_KHR : EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR};
  if (debug) {
    attribs.push_back(EGL_CONTEXT_FLAGS_KHR);
    attribs.push_back(EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR);
  }
  attribs.push_back(EGL_NONE);
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs.data());
  if (context == EGL_NO_CONTEXT) return fail(eglFailure(compatibility ? "eglCreateContext (OpenGL 4.5 compatibility)" : "eglCreateContext (OpenGL 4.5 core)"));
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    std::string reason = eglFailure("eglMakeCurrent without a surface");
    eglDestroyContext(display, context);
    return fail(reason);
  }
  return std::make_unique<EglContext>(display, context);
}

// ---------------------------------------------------------------------------------------------
// OSMesa, loaded at run time: it is the alternate provider, and linking it would pull Mesa's
// whole software stack (and LLVM) into every build that only needs EGL.
// ---------------------------------------------------------------------------------------------
struct OsMesaApi {
  decltype(&::OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&::OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&::OSMesaGetProcAddress) getProcAddress = nullptr;
  decltype(&::OSMesaDestroyContext) destroyContext = nullptr;
  std::string loadError;
};

const OsMesaApi& osMesaApi() {
  static const OsMesaApi api = [] {
    OsMesaApi a;
    void* lib = ::dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (!lib) lib = ::dlopen("libOSMesa.so", RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      a.loadError = "OSMesa: libOSMesa.so.8 not found (Debian package libosmesa6)";
      return a;
    }
    a.createContextAttribs = reinterpret_cast<decltype(a.createContextAttribs)>(::dlsym(lib, "OSMesaCreateContextAttribs"));
    a.makeCurrent = reinterpret_cast<decltype(a.makeCurrent)>(::dlsym(lib, "OSMesaMakeCurrent"));
    a.getProcAddress = reinterpret_cast<decltype(a.getProcAddress)>(::dlsym(lib, "OSMesaGetProcAddress"));
    a.destroyContext = reinterpret_cast<decltype(a.destroyContext)>(::dlsym(lib, "OSMesaDestroyContext"));
    if (!a.createContextAttribs || !a.makeCurrent || !a.getProcAddress || !a.destroyContext)
      a.loadError = "OSMesa: libOSMesa lacks OSMesaCreateContextAttribs (Mesa too old)";
    return a;
  }();
  return api;
}

class OsMesaContext final : public GlContext {
 public:
  explicit OsMesaContext(OSMesaContext context) : context_(context), dummy_(kDummySize * kDummySize * 4) {}
  ~OsMesaContext() override {
    // Unbound first, so that the context is not destroyed while current. (OSMesa still keeps the
    // buffer OSMesaMakeCurrent created: scripts/sanitizers/lsan.supp.)
    osMesaApi().makeCurrent(nullptr, nullptr, 0, 0, 0);
    osMesaApi().destroyContext(context_);
  }
  const char* providerName() const override { return "osmesa"; }
  void* getProcAddress(const char* name) override {
    return reinterpret_cast<void*>(osMesaApi().getProcAddress(name));
  }
  bool makeCurrent() override {
    // The dummy buffer is only there because OSMesa needs one to make a context current; the
    // backend renders to framebuffer objects exclusively.
    return osMesaApi().makeCurrent(context_, dummy_.data(), GL_UNSIGNED_BYTE, kDummySize, kDummySize) == GL_TRUE;
  }

 private:
  static constexpr int kDummySize = 4;
  OSMesaContext context_;
  std::vector<unsigned char> dummy_;
};

std::unique_ptr<GlContext> createOsMesa(bool /*debug: OSMesa has no debug-context attribute*/, bool compatibility,
                                        std::string* whyNot) {
  const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                         OSMESA_DEPTH_BITS, 0,
                         OSMESA_STENCIL_BITS, 0,
                         OSMESA_ACCUM_BITS, 0,
                         OSMESA_PROFILE, compatibility ? OSMESA_COMPAT_PROFILE : OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION, 4,
                         OSMESA_CONTEXT_MINOR_VERSION, 5,
                         0};
  const OsMesaApi& api = osMesaApi();
  if (!api.loadError.empty()) {
    *whyNot = api.loadError;
    return nullptr;
  }
  OSMesaContext context = api.createContextAttribs(attribs, nullptr);
  if (!context) {
    *whyNot = std::string("OSMesa: OSMesaCreateContextAttribs failed (no OpenGL 4.5 ") + (compatibility ? "compatibility" : "core") + " profile)";
    return nullptr;
  }
  auto result = std::make_unique<OsMesaContext>(context);
  if (!result->makeCurrent()) {
    *whyNot = "OSMesa: OSMesaMakeCurrent failed";
    return nullptr;
  }
  return result;
}

}  // namespace

std::unique_ptr<GlContext> createGlContext(const std::string& provider, bool debug, bool compatibility, std::string* whyNot) {
  if (provider.empty() || provider == "egl") return createEgl(debug, compatibility, whyNot);
  if (provider == "osmesa") return createOsMesa(debug, compatibility, whyNot);
  *whyNot = "unknown GL context provider '" + provider + "' (known: egl, osmesa)";
  return nullptr;
}

}  // namespace parity::rhi::gl
