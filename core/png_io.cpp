#include "core/png_io.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace sb {

namespace {

constexpr int kMaxPngSide = kMaxDepthImageSide;

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

struct PngErrorState {
  std::string message;
};

void onPngError(png_structp png, png_const_charp msg) {
  auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
  if (state) state->message = msg;
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

const char* colourTypeName(int t) {
  switch (t) {
    case PNG_COLOR_TYPE_GRAY: return "grayscale";
    case PNG_COLOR_TYPE_RGB: return "RGB";
    case PNG_COLOR_TYPE_RGBA: return "RGBA";
    case PNG_COLOR_TYPE_GRAY_ALPHA: return "grayscale+alpha";
    case PNG_COLOR_TYPE_PALETTE: return "palette";
    default: return "unknown";
  }
}

// Writes rows with libpng; `rows` point into the caller's pixel buffer.
void writePngRows(const std::string& path, int width, int height, int bitDepth, int colourType,
                  const std::vector<png_bytep>& rows, bool swap16) {
  FilePtr file(std::fopen(path.c_str(), "wb"));
  if (!file) throw Error("cannot write PNG '" + path + "': check that the directory exists and is writable");
  PngErrorState state;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw Error("libpng could not allocate a writer for '" + path + "'");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error("writing PNG '" + path + "' failed: " + state.message);
  }
  png_init_io(png, file.get());
  png_set_compression_level(png, 1);
  png_set_IHDR(png, info, width, height, bitDepth, colourType, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (swap16) png_set_swap(png);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0) throw Error("writing PNG '" + path + "' failed (disk full?)");
}

bool hostIsLittleEndian() {
  const uint16_t probe = 1;
  return *reinterpret_cast<const uint8_t*>(&probe) == 1;
}

}  // namespace

Image<uint16_t> readPng16(const std::string& path) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) throw Error("cannot open depth image '" + path + "': file missing or unreadable");
  unsigned char sig[8];
  if (std::fread(sig, 1, 8, file.get()) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
    throw Error("'" + path + "' is not a PNG file (bad signature or empty)");
  }
  PngErrorState state;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("libpng could not allocate a reader for '" + path + "'");
  }
  Image<uint16_t> image;
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("reading PNG '" + path + "' failed (truncated or corrupt?): " + state.message);
  }
  png_init_io(png, file.get());
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  const int width = static_cast<int>(png_get_image_width(png, info));
  const int height = static_cast<int>(png_get_image_height(png, info));
  const int bitDepth = png_get_bit_depth(png, info);
  const int colourType = png_get_color_type(png, info);
  if (width > kMaxPngSide || height > kMaxPngSide) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("depth image '" + path + "' claims " + std::to_string(width) + "x" + std::to_string(height) +
                " pixels; more than " + std::to_string(kMaxPngSide) + " per side is refused (corrupt header?)");
  }
  if (bitDepth != 16 || colourType != PNG_COLOR_TYPE_GRAY) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("depth image '" + path + "' is " + std::to_string(bitDepth) + "-bit " + colourTypeName(colourType) +
                "; expected 16-bit grayscale");
  }
  if (hostIsLittleEndian()) png_set_swap(png);
  image.resize(width, height);
  rows.resize(height);
  for (int y = 0; y < height; ++y) rows[y] = reinterpret_cast<png_bytep>(&image(0, y));
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

void writePng16(const std::string& path, const Image<uint16_t>& image) {
  std::vector<png_bytep> rows(image.height());
  for (int y = 0; y < image.height(); ++y)
    rows[y] = reinterpret_cast<png_bytep>(const_cast<uint16_t*>(&image(0, y)));
  writePngRows(path, image.width(), image.height(), 16, PNG_COLOR_TYPE_GRAY, rows, hostIsLittleEndian());
}

void writePngRgb(const std::string& path, const Image<Rgb8>& image) {
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be packed");
  std::vector<png_bytep> rows(image.height());
  for (int y = 0; y < image.height(); ++y)
    rows[y] = reinterpret_cast<png_bytep>(const_cast<Rgb8*>(&image(0, y)));
  writePngRows(path, image.width(), image.height(), 8, PNG_COLOR_TYPE_RGB, rows, false);
}

void writePng8(const std::string& path, const Image<uint8_t>& image) {
  std::vector<png_bytep> rows(image.height());
  for (int y = 0; y < image.height(); ++y) rows[y] = const_cast<png_bytep>(&image(0, y));
  writePngRows(path, image.width(), image.height(), 8, PNG_COLOR_TYPE_GRAY, rows, false);
}

}  // namespace sb
