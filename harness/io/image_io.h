// Images in and out of the harness, through OpenImageIO (PNG, EXR, anything OIIO reads).
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>

#include "rhi/rhi.h"

namespace parity::harness {

// Wraps texels read back from the RHI (memory row 0 first, which is the image's top row) as an
// image: 8-bit formats as UINT8 channels, float formats as FLOAT.
OIIO::ImageBuf imageFromTexels(const std::vector<uint8_t>& texels, rhi::Format format, uint32_t width,
                               uint32_t height);

// Writes atomically: to a temporary file in the destination folder, then renamed over the
// target, so an existing file is either kept or replaced whole. PNG is written as 8-bit, EXR as
// 32-bit float. Returns false with a one-line reason naming the file.
bool writeImage(const std::string& path, const OIIO::ImageBuf& image, std::string* error);

// Reads the whole image into memory. Returns false with a one-line reason naming the file.
bool readImage(const std::string& path, OIIO::ImageBuf* image, std::string* error);

}  // namespace parity::harness
