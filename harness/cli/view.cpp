// `parity view`: a window showing a technique live. Frames are rendered offscreen through the
// RHI exactly as `parity render` renders them, read back, and drawn into a GLFW window with
// glDrawPixels. This file is the only place that talks to a window.
//
// The keys change a ViewState through applyViewKey() alone, which needs no window: a scripted run
// (the hidden --keys, --print-states and --no-window options) feeds it the same key codes GLFW
// delivers, so tests drive the key handling with or without a display.
//
// Two rules shape it:
//  * The RHI's GL device owns an EGL context that is current on the thread that created it, and
//    the window's GL context must not be shared with it. So all RHI work runs on a render thread
//    and the window (context, events, presentation) stays on the main thread.
//  * GLFW is loaded with dlopen, like OSMesa in the GL backend: the parity binary then runs on
//    headless machines that have no X libraries, and only `parity view` needs them.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/io/image_io.h"
#include "rhi/timing_device.h"
#include "harness/run/render.h"
#include "platforms/common/platform.h"
#include "platforms/platform_device.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"

namespace parity::harness {

namespace {

// --- GLFW and the few GL 1.x calls presentation needs, resolved at run time ---------------------
struct WindowApi {
  void* lib = nullptr;
#define PARITY_GLFW_FUNCTIONS(X)                                                                    \
  X(glfwInit) X(glfwTerminate) X(glfwWindowHint) X(glfwCreateWindow) X(glfwDestroyWindow)            \
  X(glfwMakeContextCurrent) X(glfwSwapBuffers) X(glfwSwapInterval) X(glfwPollEvents)                 \
  X(glfwWaitEventsTimeout) X(glfwWindowShouldClose) X(glfwSetWindowShouldClose) X(glfwSetKeyCallback) \
  X(glfwSetWindowTitle) X(glfwGetFramebufferSize) X(glfwGetProcAddress) X(glfwSetErrorCallback)      \
  X(glfwSetWindowUserPointer) X(glfwGetWindowUserPointer)
#define PARITY_DECLARE(name) decltype(&::name) name = nullptr;
  PARITY_GLFW_FUNCTIONS(PARITY_DECLARE)
#undef PARITY_DECLARE

  // GL entry points of the window's own context (compatibility profile, GL 1.x calls).
  void (*glViewport)(int, int, int, int) = nullptr;
  void (*glClearColor)(float, float, float, float) = nullptr;
  void (*glClear)(unsigned) = nullptr;
  void (*glRasterPos2f)(float, float) = nullptr;
  void (*glPixelZoom)(float, float) = nullptr;
  void (*glPixelStorei)(unsigned, int) = nullptr;
  void (*glDrawPixels)(int, int, unsigned, unsigned, const void*) = nullptr;
  void (*glFinish)() = nullptr;

  bool load(std::string* error) {
    lib = ::dlopen("libglfw.so.3", RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      *error = "cannot load libglfw.so.3 (install libglfw3): " + std::string(::dlerror());
      return false;
    }
#define PARITY_RESOLVE(name)                                                  \
  name = reinterpret_cast<decltype(name)>(::dlsym(lib, #name));               \
  if (!name) {                                                                \
    *error = "libglfw.so.3 lacks " #name;                                     \
    return false;                                                             \
  }
    PARITY_GLFW_FUNCTIONS(PARITY_RESOLVE)
#undef PARITY_RESOLVE
    return true;
  }
  bool loadGl(std::string* error) {
    auto get = [&](const char* n) { return reinterpret_cast<void*>(glfwGetProcAddress(n)); };
    glViewport = reinterpret_cast<decltype(glViewport)>(get("glViewport"));
    glClearColor = reinterpret_cast<decltype(glClearColor)>(get("glClearColor"));
    glClear = reinterpret_cast<decltype(glClear)>(get("glClear"));
    glRasterPos2f = reinterpret_cast<decltype(glRasterPos2f)>(get("glRasterPos2f"));
    glPixelZoom = reinterpret_cast<decltype(glPixelZoom)>(get("glPixelZoom"));
    glPixelStorei = reinterpret_cast<decltype(glPixelStorei)>(get("glPixelStorei"));
    glDrawPixels = reinterpret_cast<decltype(glDrawPixels)>(get("glDrawPixels"));
    glFinish = reinterpret_cast<decltype(glFinish)>(get("glFinish"));
    if (!glViewport || !glClearColor || !glClear || !glRasterPos2f || !glPixelZoom || !glPixelStorei || !glDrawPixels ||
        !glFinish) {
      *error = "the window's GL context lacks the GL 1.x calls used to present (glDrawPixels, ...)";
      return false;
    }
    return true;
  }
  ~WindowApi() {
    if (lib) ::dlclose(lib);
  }
};

WindowApi* g_viewerApi = nullptr;  // for GLFW's C callbacks

constexpr unsigned kGlColorBufferBit = 0x4000, kGlRgba = 0x1908, kGlUnsignedByte = 0x1401, kGlUnpackAlignment = 0x0CF5;

std::string g_glfwError;  // GLFW reports errors through a C callback without user data
void recordGlfwError(int, const char* description) { g_glfwError = description ? description : "unknown GLFW error"; }

// --- what is shown -------------------------------------------------------------------------------
struct ViewState {
  std::string backend = "gl";
  std::string glProvider = "egl";
  std::string technique = "forward";
  std::string platform = "reference";
  std::string scene = "default";
  std::string camera = "default";
  scene::SceneParams sceneParams;
  std::string target;  // "" : the final colour
  uint32_t width = 320, height = 180;
  glm::vec3 cameraOffset{0.0f};  // moved with the keys, added to the camera's position and target
  float cameraYaw = 0.0f;        // radians, turns the view direction about the camera's up
  bool allLightsCastShadows = false;  // scene::Light::castsShadows for every light (key H)
};

// One presented frame: RGBA8 for the window plus the raw readback for --screenshot.
struct ViewFrame {
  uint64_t serial = 0;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba8;  // row 0 = top
  std::vector<uint8_t> raw;    // the shown target as read back
  rhi::Format rawFormat = rhi::Format::RGBA8;
  bool rawIsDepth = false;
  std::string targetName;
  std::vector<std::string> targetNames;
  std::vector<std::string> cameraNames;
  std::vector<rhi::PassTiming> timings;
  double frameMs = 0;  // CPU wall time of record + submit + readback
  std::string error;   // non-empty: the state could not be rendered
};

float halfToFloat(uint16_t h) {
  uint32_t sign = (h >> 15) & 1, exp = (h >> 10) & 0x1F, mant = h & 0x3FF;
  float v;
  if (exp == 0) v = std::ldexp(static_cast<float>(mant), -24);
  else if (exp == 31) v = mant ? NAN : INFINITY;
  else v = std::ldexp(static_cast<float>(mant | 0x400), static_cast<int>(exp) - 25);
  return sign ? -v : v;
}

// Any readable target as displayable RGBA8. Colour data is shown as stored (floats clamped to
// [0, 1]); depth and integer targets are stretched over their value range so structure shows.
std::vector<uint8_t> toDisplay(const std::vector<uint8_t>& raw, rhi::Format format, bool isDepth, uint32_t w,
                               uint32_t h) {
  size_t n = static_cast<size_t>(w) * h;
  std::vector<float> values(n * 4, 0.0f);
  std::vector<float> alphaDefault(n, 1.0f);
  const rhi::FormatInfo& info = rhi::formatInfo(format);
  uint32_t channels = isDepth ? 1 : info.channels;
  auto read16 = [&](size_t byteOffset) {
    uint16_t v;
    std::memcpy(&v, raw.data() + byteOffset, 2);
    return v;
  };
  bool stretch = isDepth || info.kind == rhi::FormatKind::Uint;
  for (size_t i = 0; i < n; ++i) {
    float c[4] = {0, 0, 0, 1};
    switch (isDepth ? rhi::Format::R32F : format) {
      case rhi::Format::RGBA8:
      case rhi::Format::RGBA8_SRGB:
      case rhi::Format::RGBA8_UINT:
        for (int k = 0; k < 4; ++k) c[k] = raw[i * 4 + k] / (format == rhi::Format::RGBA8_UINT ? 1.0f : 255.0f);
        break;
      case rhi::Format::R8: c[0] = raw[i] / 255.0f; break;
      case rhi::Format::RG16_UNORM:
        for (int k = 0; k < 2; ++k) c[k] = read16(i * 4 + k * 2) / 65535.0f;
        break;
      case rhi::Format::RG16_SNORM:
        for (int k = 0; k < 2; ++k) c[k] = std::max(-1.0f, static_cast<int16_t>(read16(i * 4 + k * 2)) / 32767.0f) * 0.5f + 0.5f;
        break;
      case rhi::Format::RG16_FLOAT:
        for (int k = 0; k < 2; ++k) c[k] = halfToFloat(read16(i * 4 + k * 2));
        break;
      case rhi::Format::RG16_UINT:
        for (int k = 0; k < 2; ++k) c[k] = read16(i * 4 + k * 2);
        break;
      case rhi::Format::R32_UINT: {
        uint32_t v;
        std::memcpy(&v, raw.data() + i * 4, 4);
        c[0] = static_cast<float>(v);
        break;
      }
      case rhi::Format::R32F: std::memcpy(&c[0], raw.data() + i * 4, 4); break;
      case rhi::Format::RGBA16F:
        for (int k = 0; k < 4; ++k) c[k] = halfToFloat(read16(i * 8 + k * 2));
        break;
      case rhi::Format::RG32F: std::memcpy(c, raw.data() + i * 8, 8); break;
      case rhi::Format::RGBA32F: std::memcpy(c, raw.data() + i * 16, 16); break;
      default: break;
    }
    for (int k = 0; k < 4; ++k) values[i * 4 + k] = c[k];
  }
  std::vector<uint8_t> out(n * 4);
  float lo = 0.0f, hi = 1.0f;
  if (stretch) {
    lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; ++i)
      for (uint32_t k = 0; k < std::min(channels, 3u); ++k) {
        float v = values[i * 4 + k];
        // Cleared depth (1.0) would flatten the scene's range to black: leave it out.
        if (std::isfinite(v) && !(isDepth && v >= 1.0f)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
    if (!(hi > lo)) lo = 0.0f, hi = lo + 1.0f;
  }
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      uint32_t source = channels == 1 ? 0 : static_cast<uint32_t>(k);
      float v = source < channels ? values[i * 4 + source] : 0.0f;
      if (stretch) v = (v - lo) / (hi - lo);
      if (!std::isfinite(v)) v = 0.0f;
      out[i * 4 + k] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
    out[i * 4 + 3] = 255;
  }
  return out;
}

// --- the render thread: device, scene and technique live here -------------------------------
class Renderer {
 public:
  Renderer() : thread_([this] { loop(); }) {}
  ~Renderer() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  // Asks for a frame of `state`; frames are rendered one after another for the latest state.
  void request(const ViewState& state) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      wanted_ = state;
      ++requested_;
    }
    wake_.notify_all();
  }
  // The latest finished frame, if newer than `serial`.
  std::optional<ViewFrame> frameAfter(uint64_t serial) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!latest_ || latest_->serial <= serial) return std::nullopt;
    return latest_;
  }
  // Waits up to `timeout` for a frame newer than `serial`.
  std::optional<ViewFrame> waitFrameAfter(uint64_t serial, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait_for(lock, timeout, [&] { return latest_ && latest_->serial > serial; });
    if (!latest_ || latest_->serial <= serial) return std::nullopt;
    return latest_;
  }

 private:
  struct Loaded {
    std::string backend, glProvider;
    std::unique_ptr<rhi::Device> device;
    std::unique_ptr<rhi::TimingDevice> timed;
    std::unique_ptr<platforms::PlatformDevice> onPlatform;  // over `timed`: the technique's device
    // What the scene and technique were built for.
    std::string technique, platform, scene;
    scene::SceneParams sceneParams{};
    bool allLightsCastShadows = false;
    uint32_t width = 0, height = 0;
    scene::Scene cpuScene;
    std::unique_ptr<scene::SceneGpu> gpuScene;
    std::unique_ptr<techniques::Technique> tech;
  };

  void releaseScene() {
    if (loaded_.tech && loaded_.onPlatform) loaded_.tech->release(*loaded_.onPlatform);
    loaded_.tech.reset();
    loaded_.onPlatform.reset();
    loaded_.gpuScene.reset();
    loaded_.technique.clear();
  }

  // Brings device, scene and technique up to `s`; throws std::runtime_error with a reason.
  void load(const ViewState& s) {
    if (!loaded_.device || loaded_.backend != s.backend || loaded_.glProvider != s.glProvider) {
      releaseScene();
      loaded_.timed.reset();
      loaded_.device.reset();
      rhi::DeviceDesc desc;
      desc.backend = s.backend;
      desc.glContextProvider = s.glProvider;
      std::string why;
      loaded_.device = rhi::createDevice(desc, &why);
      if (!loaded_.device) throw std::runtime_error("backend " + s.backend + " unavailable: " + why);
      loaded_.timed = std::make_unique<rhi::TimingDevice>(*loaded_.device);
      loaded_.backend = s.backend;
      loaded_.glProvider = s.glProvider;
    }
    bool sameScene = loaded_.tech && loaded_.technique == s.technique && loaded_.platform == s.platform &&
                     loaded_.scene == s.scene && loaded_.sceneParams.lightCount == s.sceneParams.lightCount &&
                     loaded_.sceneParams.lightSize == s.sceneParams.lightSize &&
                     loaded_.sceneParams.seed == s.sceneParams.seed &&
                     loaded_.allLightsCastShadows == s.allLightsCastShadows && loaded_.width == s.width &&
                     loaded_.height == s.height;
    if (sameScene) return;
    releaseScene();
    std::string error;
    scene::Scene cpu;
    if (!scene::makeScene(s.scene, s.sceneParams, &cpu, &error)) throw std::runtime_error(error);
    for (scene::Light& light : cpu.lights) light.castsShadows = s.allLightsCastShadows;
    std::optional<platforms::PlatformId> platform = platforms::platformFromName(s.platform);
    if (!platform) throw std::runtime_error("unknown platform '" + s.platform + "'");
    std::unique_ptr<techniques::Technique> tech = techniques::createTechnique(s.technique);
    if (!tech) throw std::runtime_error("unknown technique '" + s.technique + "'");
    loaded_.cpuScene = std::move(cpu);
    loaded_.gpuScene = std::make_unique<scene::SceneGpu>(*loaded_.timed, loaded_.cpuScene);
    techniques::RenderSettings settings;
    settings.width = s.width;
    settings.height = s.height;
    settings.colorFormat = rhi::Format::RGBA8;
    settings.platform = *platform;
    loaded_.onPlatform =
        std::make_unique<platforms::PlatformDevice>(*loaded_.timed, *platform, settings.platformParams, false);
    tech->prepare(*loaded_.onPlatform, settings);
    loaded_.tech = std::move(tech);
    loaded_.technique = s.technique;
    loaded_.platform = s.platform;
    loaded_.scene = s.scene;
    loaded_.sceneParams = s.sceneParams;
    loaded_.allLightsCastShadows = s.allLightsCastShadows;
    loaded_.width = s.width;
    loaded_.height = s.height;
  }

  ViewFrame renderOne(const ViewState& s) {
    ViewFrame f;
    auto start = std::chrono::steady_clock::now();
    load(s);
    const scene::Camera* named = loaded_.cpuScene.camera(s.camera);
    if (!named) named = &loaded_.cpuScene.cameras.at(0);
    scene::Camera camera = *named;
    if (s.cameraYaw != 0.0f) {
      glm::vec3 forward = camera.target - camera.position;
      glm::vec3 up = glm::normalize(camera.up);
      float c = std::cos(s.cameraYaw), sn = std::sin(s.cameraYaw);
      // Rodrigues' rotation of the view direction about the up axis.
      forward = forward * c + glm::cross(up, forward) * sn + up * glm::dot(up, forward) * (1.0f - c);
      camera.target = camera.position + forward;
    }
    camera.position += s.cameraOffset;
    camera.target += s.cameraOffset;
    for (const scene::Camera& c : loaded_.cpuScene.cameras) f.cameraNames.push_back(c.name);

    loaded_.timed->beginFrame();
    rhi::TextureHandle color = loaded_.tech->render(*loaded_.onPlatform, *loaded_.gpuScene, camera);
    loaded_.timed->submit();
    f.timings = loaded_.timed->passTimings();

    rhi::TextureHandle shown = color;
    f.targetName = "color";
    std::vector<techniques::NamedTarget> targets = loaded_.tech->targets();
    for (const techniques::NamedTarget& t : targets) {
      f.targetNames.push_back(t.name);
      if (!s.target.empty() && t.name == s.target) shown = t.texture, f.targetName = t.name;
    }
    const rhi::TextureDesc* desc = loaded_.timed->describe(shown);
    if (!desc) throw std::runtime_error("target '" + f.targetName + "' is not readable");
    if (desc->samples > 1) throw std::runtime_error("target '" + f.targetName + "' is multisampled and cannot be shown");
    f.rawIsDepth = rhi::isDepthFormat(desc->format);
    rhi::ReadbackRegion region;
    if (f.rawIsDepth) region.aspect = rhi::TextureAspect::Depth;
    f.raw = loaded_.timed->readTexture(shown, region);
    f.rawFormat = desc->format;
    f.width = desc->width;
    f.height = desc->height;
    size_t texelBytes = f.rawIsDepth ? 4 : rhi::formatInfo(desc->format).bytesPerTexel;
    if (f.raw.size() != static_cast<size_t>(f.width) * f.height * texelBytes)
      throw std::runtime_error("target '" + f.targetName + "' could not be read back");
    f.rgba8 = toDisplay(f.raw, f.rawFormat, f.rawIsDepth, f.width, f.height);
    f.frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return f;
  }

  void loop() {
    uint64_t rendered = 0;
    for (;;) {
      ViewState s;
      uint64_t serial;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return quit_ || requested_ > rendered; });
        if (quit_) break;
        s = wanted_;
        serial = requested_;
      }
      ViewFrame f;
      try {
        f = renderOne(s);
      } catch (const std::exception& e) {
        f.error = e.what();
        releaseScene();  // a failed prepare leaves nothing half-built behind
      }
      f.serial = serial;
      rendered = serial;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        latest_ = std::move(f);
      }
      done_.notify_all();
    }
    releaseScene();
    loaded_.timed.reset();
    loaded_.device.reset();
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  bool quit_ = false;
  ViewState wanted_;
  uint64_t requested_ = 0;
  std::optional<ViewFrame> latest_;
  Loaded loaded_;
  std::thread thread_;  // last: starts after the members above exist
};

struct ViewOptions {
  ViewState state;
  std::string size = "320x180";
  std::string lightSize = "small";
  uint32_t frames = 0;     // 0: until the window is closed
  std::string screenshot;  // written from the last frame's readback
  uint32_t scale = 2;      // window pixels per image pixel
  // Scripted runs (tests): keys pressed one per frame after the first, a JSON line per frame,
  // and rendering without a window.
  std::string keys;
  bool printStates = false;
  bool noWindow = false;
};

template <class T>
size_t indexOf(const std::vector<T>& list, const T& value) {
  auto it = std::find(list.begin(), list.end(), value);
  return it == list.end() ? 0 : static_cast<size_t>(it - list.begin());
}
template <class T>
const T& cycle(const std::vector<T>& list, const T& current, int step) {
  size_t n = list.size();
  size_t i = (indexOf(list, current) + n + static_cast<size_t>(step + static_cast<int>(n))) % n;
  return list[i];
}

// The lists the cycling keys step through. Targets and cameras are those of the last frame.
struct ViewChoices {
  std::vector<std::string> techniques, platforms{"reference", "dx10", "ps3", "x360"}, scenes;
  std::vector<std::string> targets{"color"}, cameras{"default"};
};

ViewChoices initialChoices() {
  ViewChoices c;
  for (const auto& t : techniques::techniqueRegistry()) c.techniques.push_back(t.name);
  c.scenes = scene::sceneNames();
  return c;
}

// What one key does to the state (the keys the `view` help lists). Returns false for a key with
// no meaning, which leaves the state as it is.
bool applyViewKey(ViewState& state, int key, int mods, const ViewChoices& choices) {
  int step = (mods & GLFW_MOD_SHIFT) ? -1 : 1;
  const float move = 0.25f;
  switch (key) {
    case GLFW_KEY_T: state.technique = cycle(choices.techniques, state.technique, step), state.target.clear(); break;
    case GLFW_KEY_B: state.backend = state.backend == "gl" ? "vk" : "gl"; break;
    case GLFW_KEY_P: state.platform = cycle(choices.platforms, state.platform, step); break;
    case GLFW_KEY_N: state.scene = cycle(choices.scenes, state.scene, step), state.camera = "default"; break;
    case GLFW_KEY_C: state.camera = cycle(choices.cameras, state.camera, step), state.cameraOffset = {}, state.cameraYaw = 0; break;
    case GLFW_KEY_TAB:
    case GLFW_KEY_G: {
      std::string current = state.target.empty() ? "color" : state.target;
      state.target = cycle(choices.targets, current, step);
      break;
    }
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: state.sceneParams.lightCount = std::min(4096u, std::max(1u, state.sceneParams.lightCount * 2)); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: state.sceneParams.lightCount /= 2; break;
    case GLFW_KEY_L:
      state.sceneParams.lightSize =
          state.sceneParams.lightSize == scene::LightSize::Small ? scene::LightSize::Big : scene::LightSize::Small;
      break;
    case GLFW_KEY_W: case GLFW_KEY_UP: state.cameraOffset.z -= move; break;
    case GLFW_KEY_S: case GLFW_KEY_DOWN: state.cameraOffset.z += move; break;
    case GLFW_KEY_A: state.cameraOffset.x -= move; break;
    case GLFW_KEY_D: state.cameraOffset.x += move; break;
    case GLFW_KEY_Q: state.cameraOffset.y -= move; break;
    case GLFW_KEY_E: state.cameraOffset.y += move; break;
    case GLFW_KEY_LEFT: state.cameraYaw += 0.05f; break;
    case GLFW_KEY_RIGHT: state.cameraYaw -= 0.05f; break;
    case GLFW_KEY_R: state.cameraOffset = {}, state.cameraYaw = 0; break;
    case GLFW_KEY_H: state.allLightsCastShadows = !state.allLightsCastShadows; break;
    default: return false;
  }
  return true;
}

struct KeyPress {
  int key = GLFW_KEY_UNKNOWN, mods = 0;
  std::string name;  // as written in the script
};

// A scripted key sequence: names separated by blanks or commas; a letter (either case), tab,
// up, down, left, right, + (or plus), - (or minus), each optionally prefixed "shift+".
bool parseKeySequence(const std::string& text, std::vector<KeyPress>* out, std::string* error) {
  std::string token;
  auto finish = [&]() -> bool {
    if (token.empty()) return true;
    KeyPress k;
    k.name = token;
    std::string name = token;
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (name.rfind("shift+", 0) == 0 && name.size() > 6) k.mods = GLFW_MOD_SHIFT, name = name.substr(6);
    static const std::map<std::string, int> named = {
        {"tab", GLFW_KEY_TAB},     {"up", GLFW_KEY_UP},     {"down", GLFW_KEY_DOWN}, {"left", GLFW_KEY_LEFT},
        {"right", GLFW_KEY_RIGHT}, {"+", GLFW_KEY_KP_ADD}, {"plus", GLFW_KEY_KP_ADD}, {"-", GLFW_KEY_MINUS},
        {"minus", GLFW_KEY_MINUS}};
    if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z') k.key = GLFW_KEY_A + (name[0] - 'a');
    else if (auto it = named.find(name); it != named.end()) k.key = it->second;
    else {
      *error = "unknown key '" + token + "' (letters, tab, up, down, left, right, +, -, each with an optional shift+)";
      return false;
    }
    out->push_back(k);
    token.clear();
    return true;
  };
  for (char c : text) {
    if (c == ' ' || c == ',' || c == '\t') {
      if (!finish()) return false;
    } else {
      token += c;
    }
  }
  return finish();
}

struct ViewerWindow {
  ViewState& state;
  ViewChoices choices = initialChoices();
  bool changed = true;

  void onKey(int key, int mods) {
    if (applyViewKey(state, key, mods, choices)) changed = true;
  }
};

void keyCallback(GLFWwindow* window, int key, int, int action, int mods) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  // The key callback is a C function pointer: the window carries the viewer in its user pointer.
  auto* self = static_cast<ViewerWindow*>(g_viewerApi->glfwGetWindowUserPointer(window));
  if (key == GLFW_KEY_ESCAPE) {
    g_viewerApi->glfwSetWindowShouldClose(window, GLFW_TRUE);
    return;
  }
  self->onKey(key, mods);
}

std::string titleOf(const ViewState& s, const ViewFrame& f) {
  char buf[96];
  std::string title = "parity view | " + s.technique + " | " + s.backend + " | " + s.platform + " | " + s.scene + "/" +
                      s.camera + " | " + std::to_string(s.sceneParams.lightCount) + (s.allLightsCastShadows ? " shadowed" : "") + " lights | " +
                      f.targetName;
  if (!f.error.empty()) return title + " | error: " + f.error;
  // Passes sharing a label (one per light, say) are summed, so the title stays readable.
  std::vector<std::pair<std::string, std::pair<double, int>>> byLabel;
  double gpu = 0;
  for (const rhi::PassTiming& p : f.timings) {
    auto it = std::find_if(byLabel.begin(), byLabel.end(), [&](const auto& e) { return e.first == p.label; });
    if (it == byLabel.end()) it = byLabel.insert(byLabel.end(), {p.label, {0.0, 0}});
    it->second.first += p.ms;
    ++it->second.second;
    gpu += p.ms;
  }
  std::string passes;
  for (const auto& [label, sum] : byLabel) {
    if (sum.second > 1) std::snprintf(buf, sizeof buf, " %s x%d %.2f", label.c_str(), sum.second, sum.first);
    else std::snprintf(buf, sizeof buf, " %s %.2f", label.c_str(), sum.first);
    passes += buf;
  }
  std::snprintf(buf, sizeof buf, " | frame %.1f ms (passes %.2f ms):", f.frameMs, gpu);
  return title + buf + passes;
}

// One shown frame of a scripted run as a JSON line: the state, the key that led to it and what
// the frame offered the cycling keys.
std::string stateLine(const ViewState& s, const ViewFrame& f, const std::string& key) {
  nlohmann::json j = {{"key", key},
                      {"technique", s.technique},
                      {"backend", s.backend},
                      {"platform", s.platform},
                      {"scene", s.scene},
                      {"camera", s.camera},
                      {"lights", s.sceneParams.lightCount},
                      {"lightSize", s.sceneParams.lightSize == scene::LightSize::Big ? "big" : "small"},
                      {"allLightsCastShadows", s.allLightsCastShadows},
                      {"cameraOffset", {s.cameraOffset.x, s.cameraOffset.y, s.cameraOffset.z}},
                      {"cameraYaw", s.cameraYaw},
                      {"target", s.target},
                      {"shown", f.targetName},
                      {"targets", nlohmann::json::array()},
                      {"cameras", f.cameraNames}};
  j["targets"].push_back("color");
  for (const std::string& n : f.targetNames)
    if (n != "color") j["targets"].push_back(n);
  return j.dump();
}

// Window and presentation; absent (all calls no-ops) with --no-window.
struct Presenter {
  WindowApi api;
  GLFWwindow* window = nullptr;
  std::vector<uint8_t> flipped;

  // Returns an error message, or "" when the window is up.
  std::string open(const ViewState& s, const ViewOptions& o, ViewerWindow* viewer) {
    std::string error;
    if (!api.load(&error)) return error;
    g_viewerApi = &api;
    api.glfwSetErrorCallback(recordGlfwError);
    if (!api.glfwInit()) return "cannot open a window (is DISPLAY set? try xvfb-run): " + g_glfwError;
    api.glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    api.glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window = api.glfwCreateWindow(static_cast<int>(s.width * o.scale), static_cast<int>(s.height * o.scale),
                                  "parity view", nullptr, nullptr);
    if (!window) {
      api.glfwTerminate();
      return "cannot create a window: " + g_glfwError;
    }
    api.glfwMakeContextCurrent(window);
    if (!api.loadGl(&error)) {
      close();
      return error;
    }
    api.glfwSwapInterval(o.frames > 0 ? 0 : 1);
    api.glfwSetWindowUserPointer(window, viewer);
    api.glfwSetKeyCallback(window, keyCallback);
    return "";
  }
  bool shouldClose() const { return window && api.glfwWindowShouldClose(window); }
  void setTitle(const std::string& title) {
    if (window) api.glfwSetWindowTitle(window, title.c_str());
  }
  void present(const std::optional<ViewFrame>& last) {
    if (!window) return;
    int fbw = 0, fbh = 0;
    api.glfwGetFramebufferSize(window, &fbw, &fbh);
    api.glViewport(0, 0, fbw, fbh);
    api.glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
    api.glClear(kGlColorBufferBit);
    if (last && last->width > 0 && fbw > 0 && fbh > 0) {
      // glDrawPixels takes the bottom row first; the readback is top row first.
      size_t row = static_cast<size_t>(last->width) * 4;
      flipped.resize(last->rgba8.size());
      for (uint32_t y = 0; y < last->height; ++y)
        std::memcpy(flipped.data() + (last->height - 1 - y) * row, last->rgba8.data() + y * row, row);
      api.glPixelStorei(kGlUnpackAlignment, 1);
      api.glRasterPos2f(-1.0f, -1.0f);
      api.glPixelZoom(static_cast<float>(fbw) / last->width, static_cast<float>(fbh) / last->height);
      api.glDrawPixels(static_cast<int>(last->width), static_cast<int>(last->height), kGlRgba, kGlUnsignedByte,
                       flipped.data());
    }
    api.glfwSwapBuffers(window);
  }
  void pollEvents(bool wait) {
    if (!window) return;
    if (wait) api.glfwWaitEventsTimeout(0.05);
    else api.glfwPollEvents();
  }
  void close() {
    if (window) api.glfwDestroyWindow(window);
    if (api.glfwTerminate) api.glfwTerminate();
    window = nullptr;
    g_viewerApi = nullptr;
  }
  ~Presenter() {
    if (g_viewerApi == &api) close();
  }
};

int cmdView(ViewOptions& o) {
  ViewState& s = o.state;
  std::string error;
  if (!parseSize(o.size, &s.width, &s.height, &error)) return reportError("view: " + error);
  s.sceneParams.lightSize = o.lightSize == "big" ? scene::LightSize::Big : scene::LightSize::Small;
  if (!platforms::platformFromName(s.platform))
    return reportError("view: unknown platform '" + s.platform + "' (known: reference, dx10, ps3, x360)");
  if (!techniques::createTechnique(s.technique)) return reportError("view: unknown technique '" + s.technique + "'");
  if (!o.screenshot.empty()) {
    std::string ext = o.screenshot.substr(o.screenshot.find_last_of('.') == std::string::npos ? o.screenshot.size()
                                                                                              : o.screenshot.find_last_of('.'));
    if (ext != ".png" && ext != ".exr") return reportError("view: " + o.screenshot + ": screenshot must be .png or .exr");
  }
  std::vector<KeyPress> keys;
  if (!parseKeySequence(o.keys, &keys, &error)) return reportError("view: --keys: " + error);
  // A scripted or windowless run must end by itself: one frame after the last key at least.
  uint32_t frames = o.frames;
  if (frames == 0 && (o.noWindow || !keys.empty())) frames = 1;

  ViewerWindow viewer{s};
  Presenter presenter;
  if (!o.noWindow) {
    error = presenter.open(s, o, &viewer);
    if (!error.empty()) return reportError("view: " + error);
  }

  int exitCode = 0;
  {
    Renderer renderer;
    uint64_t shownSerial = 0;
    uint32_t framesShown = 0;
    size_t nextKey = 0;
    std::string lastKey;
    std::optional<ViewFrame> last;
    while (!presenter.shouldClose()) {
      if (viewer.changed || frames > 0) {
        // Live view re-renders only on change; --frames renders back to back.
        if (viewer.changed || !last || last->serial == shownSerial) renderer.request(s);
        viewer.changed = false;
      }
      std::optional<ViewFrame> f = frames > 0 ? renderer.waitFrameAfter(shownSerial, std::chrono::seconds(120))
                                              : renderer.frameAfter(shownSerial);
      if (frames > 0 && !f) {
        exitCode = reportError("view: no frame within 120 s");
        break;
      }
      if (f) {
        shownSerial = f->serial;
        if (!f->targetNames.empty()) {
          viewer.choices.targets = {"color"};
          for (const std::string& n : f->targetNames)
            if (n != "color") viewer.choices.targets.push_back(n);
        }
        if (!f->cameraNames.empty()) viewer.choices.cameras = f->cameraNames;
        presenter.setTitle(titleOf(s, *f));
        if (!f->error.empty() && frames > 0) {
          exitCode = reportError("view: " + f->error);
          break;
        }
        if (o.printStates) std::printf("%s\n", stateLine(s, *f, lastKey).c_str());
        if (f->error.empty()) last = std::move(f);
        // A scripted key is pressed once the frame of the state before it is shown, so every
        // key acts on the target and camera lists of the technique and scene it sees; the
        // frames --frames counts are those after the last key.
        if (nextKey < keys.size()) {
          lastKey = keys[nextKey].name;
          viewer.onKey(keys[nextKey].key, keys[nextKey].mods);
          viewer.changed = true;  // a key without meaning still gets its frame (and its line)
          ++nextKey;
        } else {
          ++framesShown;
        }
      }
      presenter.present(last);
      if (frames > 0 && framesShown >= frames) break;
      presenter.pollEvents(frames == 0);
    }
    // A headless run (--frames) has nobody reading the title: print the last one.
    if (exitCode == 0 && frames > 0 && last && !o.printStates) std::printf("%s\n", titleOf(s, *last).c_str());
    if (exitCode == 0 && !o.screenshot.empty()) {
      if (!last) {
        exitCode = reportError("view: " + o.screenshot + ": no frame was rendered");
      } else {
        // The shown target exactly as read back, as `parity render` writes the final colour.
        rhi::Format format = last->rawIsDepth ? rhi::Format::R32F : last->rawFormat;
        std::string writeError;
        if (!writeImage(o.screenshot, imageFromTexels(last->raw, format, last->width, last->height), &writeError))
          exitCode = reportError("view: " + writeError);
      }
    }
  }
  presenter.close();
  return exitCode;
}

}  // namespace

void registerViewCommand(CLI::App& app, CommandSet& commands) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* view = app.add_subcommand(
      "view",
      "show a technique live in a window. Keys: T technique, B backend, P platform, N scene, C camera, "
      "G/Tab target shown, +/- light count, L light size, H shadows from every light, WASD/QE/arrows move, "
      "R reset camera, Esc quit "
      "(Shift reverses T, P, N, C, G)");
  view->add_option("--technique,-t", o->state.technique, "technique name (see `parity list`)")->capture_default_str();
  view->add_option("--backend,-b", o->state.backend, "gl or vk")->check(CLI::IsMember({"gl", "vk"}))->capture_default_str();
  view->add_option("--platform,-p", o->state.platform, "platform layer: reference, dx10, ps3 or x360")->capture_default_str();
  view->add_option("--scene", o->state.scene, "scene name")->capture_default_str();
  view->add_option("--camera", o->state.camera, "camera of the scene")->capture_default_str();
  view->add_option("--size", o->size, "image size WIDTHxHEIGHT")->capture_default_str();
  view->add_option("--lights", o->state.sceneParams.lightCount, "number of local lights")->capture_default_str();
  view->add_option("--light-size", o->lightSize, "small or big")->check(CLI::IsMember({"small", "big"}))->capture_default_str();
  view->add_option("--seed", o->state.sceneParams.seed, "seed for light placement")->capture_default_str();
  view->add_option("--target", o->state.target, "target shown (a name of Technique::targets(); default: the final colour)");
  view->add_option("--gl-provider", o->state.glProvider, "GL context provider")->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  view->add_flag("--all-lights-cast-shadows", o->state.allLightsCastShadows,
                 "start with scene::Light::castsShadows set on every light (key H toggles it)");
  view->add_option("--frames", o->frames, "render this many frames back to back, then exit (0: until closed)")->capture_default_str();
  view->add_option("--screenshot", o->screenshot, "write the last frame's read-back target here (.png or .exr)");
  view->add_option("--scale", o->scale, "window pixels per image pixel")->check(CLI::Range(1u, 8u))->capture_default_str();
  // Tests only: KEYS pressed one per frame after the first (e.g. "T shift+P tab + W left"), the
  // state of every shown frame as a JSON line on stdout, and rendering without a window.
  view->add_option("--keys", o->keys, "")->group("");
  view->add_flag("--print-states", o->printStates, "")->group("");
  view->add_flag("--no-window", o->noWindow, "")->group("");
  commands.add(view, [o] { return cmdView(*o); });
}

}  // namespace parity::harness
