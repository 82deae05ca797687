#pragma once
// In-memory PNG encoding and decoding for the report (images embedded as data: URIs).

#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/png_io.h"

namespace sb::report {

// Reads a whole file. Throws sb::Error naming the file if it cannot be read.
std::vector<uint8_t> readFileBytes(const std::string& path);

// Decodes any PNG (gray, gray+alpha, RGB, RGBA, palette; 1-16 bit) to 8-bit luminance; alpha is dropped.
// `name` is used in errors. Throws sb::Error when the bytes are not a complete PNG or a side exceeds 16384.
Image<uint8_t> decodePngGray(const std::vector<uint8_t>& png, const std::string& name);

std::vector<uint8_t> encodePng(const Image<uint8_t>& image);
std::vector<uint8_t> encodePng(const Image<Rgb8>& image);

}  // namespace sb::report
