#pragma once
// PNG files through libpng. Errors name the file and what was found.

#include <cstdint>
#include <string>

#include "core/image.h"

namespace sb {

// Reads a 16-bit single-channel PNG. Throws sb::Error if the file is missing, truncated, not a PNG, or not
// 16-bit grayscale (the message says which bit depth / colour type it has).
Image<uint16_t> readPng16(const std::string& path);

// Writes a 16-bit grayscale PNG (fast compression). Throws sb::Error on failure.
void writePng16(const std::string& path, const Image<uint16_t>& image);

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
};

// Writes an 8-bit grayscale PNG. Throws sb::Error on failure.
void writePng8(const std::string& path, const Image<uint8_t>& image);

}  // namespace sb
