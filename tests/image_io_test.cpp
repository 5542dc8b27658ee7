// Image files hold the texels as rendered. A data target's alpha is data (a light index chunk, a
// specular power), not coverage: where it is 0 the colour channels must survive the PNG and EXR
// round trip (OpenImageIO would otherwise take PNG alpha as premultiplication to undo and store 0).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <vector>

#include "harness/io/image_io.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

TEST(ImageIo, TexelsWithZeroAlphaSurviveTheRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("parity-image-io-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::vector<uint8_t> rgba8 = {10, 20, 30, 0, 200, 100, 50, 0, 1, 2, 3, 4, 255, 0, 128, 255};
  const float f[16] = {0.5f, 0.25f, 2.0f, 0.0f, 1.0f, 0.0f, 0.125f, 0.0f, 3.0f, 4.0f, 5.0f, 1.0f, 0, 0, 0, 0};
  std::vector<uint8_t> rgba32f(sizeof f);
  std::memcpy(rgba32f.data(), f, sizeof f);
  struct Case {
    rhi::Format format;
    const std::vector<uint8_t>* texels;
    const char* file;
  };
  for (const Case& c : {Case{rhi::Format::RGBA8, &rgba8, "a.png"}, Case{rhi::Format::RGBA32F, &rgba32f, "a.exr"}}) {
    std::string error;
    const std::string path = (dir / c.file).string();
    ASSERT_TRUE(harness::writeImage(path, harness::imageFromTexels(*c.texels, c.format, 2, 2), &error)) << error;
    OIIO::ImageBuf back;
    ASSERT_TRUE(harness::readImage(path, &back, &error)) << error;
    const bool isFloat = c.format == rhi::Format::RGBA32F;
    std::vector<uint8_t> got(c.texels->size());
    back.get_pixels(OIIO::ROI::All(), isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, got.data());
    EXPECT_EQ(got, *c.texels) << c.file;
  }
  fs::remove_all(dir);
}

}  // namespace
