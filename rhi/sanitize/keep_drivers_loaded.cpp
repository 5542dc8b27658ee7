// Sanitizer builds only (PARITY_SANITIZE, CMakeLists.txt): dlclose() keeps every library loaded.
//
// Why: the Vulkan loader unloads the ICD (lavapipe) in vkDestroyInstance and Mesa's EGL unloads
// its driver in eglTerminate. LeakSanitizer reports leaks at exit, when those libraries are gone:
// their allocation stacks then read "<unknown module>", so a driver's leak can neither be told
// apart from parity's nor suppressed by library name. With the libraries still mapped, every
// frame is symbolised and scripts/sanitizers/lsan.supp can name the driver that leaks.
//
// Defined in each executable, this dlclose() takes precedence over libc's for every caller,
// the loaders included. Nothing relies on a library actually being unmapped.
extern "C" int dlclose(void*) { return 0; }
