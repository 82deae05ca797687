#include "core/png_io.h"

#include <png.h>

#include <csetjmp>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <memory>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/input_file.h"

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

// Where libpng's writes go, and the system's reason when one fails (libpng itself only says "Write Error").
struct PngSink {
  FILE* file = nullptr;
  int error = 0;  // errno of the failed write or flush
};

void writePngData(png_structp png, png_bytep data, png_size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  errno = 0;
  if (std::fwrite(data, 1, length, sink->file) != length) {
    sink->error = errno ? errno : EIO;
    png_error(png, "write failed");
  }
}

void flushPngData(png_structp png) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  if (std::fflush(sink->file) != 0) {
    sink->error = errno ? errno : EIO;
    png_error(png, "flush failed");
  }
}

// Writes rows with libpng to `file` exactly as given; `rows` point into the caller's pixel buffer.
void writePngRowsTo(std::FILE* file, const std::string& name, int width, int height, int bitDepth,
                    int colourType, const std::vector<png_bytep>& rows, bool swap16) {
  PngErrorState state;
  PngSink sink{file, 0};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw Error("libpng could not allocate a writer for '" + name + "'");
  }
  const auto failed = [&](const std::string& what) {
    return Error("writing PNG '" + name + "' failed: " + what + "; the previous file (if any) is left as it was" +
                 (sink.error == ENOSPC ? " (free disk space and run again)" : ""));
  };
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw failed(sink.error ? std::strerror(sink.error) : state.message);
  }
  png_set_write_fn(png, &sink, writePngData, flushPngData);
  png_set_compression_level(png, 1);
  png_set_IHDR(png, info, width, height, bitDepth, colourType, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (swap16) png_set_swap(png);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  errno = 0;
  if (std::fflush(file) != 0) throw failed(std::strerror(errno ? errno : EIO));
}

// Whole or not at all: the PNG is written to a temporary sibling and renamed over `path` once complete.
void writePngRows(const std::string& path, int width, int height, int bitDepth, int colourType,
                  const std::vector<png_bytep>& rows, bool swap16) {
  writeFileAtomically(path, [&](std::FILE* file, const std::string&) {
    writePngRowsTo(file, path, width, height, bitDepth, colourType, rows, swap16);
  });
}

bool hostIsLittleEndian() {
  const uint16_t probe = 1;
  return *reinterpret_cast<const uint8_t*>(&probe) == 1;
}

}  // namespace

Image<uint16_t> readPng16(const std::string& path) {
  // Opened without blocking and checked to be a regular file (a FIFO or device is refused, never waited on).
  UniqueFd fd = openRegularFile(path, "depth image");
  FilePtr file(::fdopen(fd.get(), "rb"));
  if (!file) throw Error("cannot open depth image " + quoteForMessage(path) + ": " + std::strerror(errno));
  fd.release();  // the FILE owns it now
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

void writePng8(const std::string& path, const Image<uint8_t>& image) {
  std::vector<png_bytep> rows(image.height());
  for (int y = 0; y < image.height(); ++y) rows[y] = const_cast<png_bytep>(&image(0, y));
  writePngRows(path, image.width(), image.height(), 8, PNG_COLOR_TYPE_GRAY, rows, false);
}

}  // namespace sb
