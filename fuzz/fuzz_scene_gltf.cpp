// Scene loader on .gltf input: any byte string must load or fail with a message, never crash,
// hang or read outside the file's folder.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_file.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  parity::fuzz::InputFile file(data, size, ".gltf");
  parity::scene::SceneParams params;
  params.lightCount = 4;  // light placement runs too, but stays cheap
  parity::scene::Scene scene;
  std::string error;
  parity::scene::loadSceneFile(file.path(), params, &scene, &error);
  return 0;
}
