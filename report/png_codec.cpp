#include "report/png_codec.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/input_file.h"

namespace sb::report {

namespace {

constexpr png_uint_32 kMaxSide = 16384;  // a corrupt header must not make us allocate gigabytes

struct ReadState {
  const std::vector<uint8_t>* bytes = nullptr;
  size_t offset = 0;
  char message[256] = {};
};

void onError(png_structp png, png_const_charp msg) {
  auto* state = static_cast<ReadState*>(png_get_error_ptr(png));
  if (state) std::snprintf(state->message, sizeof state->message, "%s", msg);
  png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

void readFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* state = static_cast<ReadState*>(png_get_io_ptr(png));
  if (state->offset + length > state->bytes->size()) png_error(png, "file ends early (truncated PNG)");
  std::memcpy(out, state->bytes->data() + state->offset, length);
  state->offset += length;
}

void writeToMemory(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void flushNothing(png_structp) {}

std::vector<uint8_t> encodeRows(int width, int height, int colourType, const uint8_t* pixels, int channels) {
  std::vector<uint8_t> out;
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y)
    rows[static_cast<size_t>(y)] = const_cast<png_bytep>(pixels + static_cast<size_t>(y) * width * channels);
  ReadState state;  // only its message is used
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw Error("libpng could not allocate a PNG encoder");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error(std::string("PNG encoding failed: ") + state.message);
  }
  png_set_write_fn(png, &out, writeToMemory, flushNothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, colourType,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace

std::vector<uint8_t> readFileBytes(const std::string& path) {
  InputFile in(path, "file");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error("error while reading '" + path + "'");
  return bytes;
}

Image<uint8_t> decodePngGray(const std::vector<uint8_t>& bytes, const std::string& name) {
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0)
    throw Error("'" + name + "' is not a PNG file (bad signature)");
  ReadState state;
  state.bytes = &bytes;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("libpng could not allocate a PNG decoder for '" + name + "'");
  }
  Image<uint8_t> image;             // constructed before setjmp: no C++ object is skipped by longjmp
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error("cannot decode PNG '" + name + "': " + state.message);
  }
  png_set_read_fn(png, &state, readFromMemory);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide)
    png_error(png, "image size out of range (1..16384 px per side)");
  const int colourType = png_get_color_type(png, info);
  if (png_get_bit_depth(png, info) == 16) png_set_strip_16(png);
  if (colourType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colourType == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (colourType & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
  if (colourType == PNG_COLOR_TYPE_RGB || colourType == PNG_COLOR_TYPE_RGB_ALPHA ||
      colourType == PNG_COLOR_TYPE_PALETTE)
    png_set_rgb_to_gray_fixed(png, 1, -1, -1);  // default (Rec. 709) weights, no error on colour
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != width) png_error(png, "unexpected row size after conversion to gray");
  image.resize(static_cast<int>(width), static_cast<int>(height));
  rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image.data() + static_cast<size_t>(y) * width;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

std::vector<uint8_t> encodePng(const Image<uint8_t>& image) {
  if (image.empty()) throw Error("cannot encode an empty image as PNG");
  return encodeRows(image.width(), image.height(), PNG_COLOR_TYPE_GRAY, image.data(), 1);
}

std::vector<uint8_t> encodePng(const Image<Rgb8>& image) {
  if (image.empty()) throw Error("cannot encode an empty image as PNG");
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be packed");
  return encodeRows(image.width(), image.height(), PNG_COLOR_TYPE_RGB,
                    reinterpret_cast<const uint8_t*>(image.data()), 3);
}

}  // namespace sb::report
