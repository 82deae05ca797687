#pragma once
// An std::ostream over a stdio stream (a TemporaryFile's, core/exclusive_file.h): writers that format with
// iostreams write into a file opened by descriptor. Unbuffered here; stdio buffers.

#include <cstdio>
#include <streambuf>

namespace sb {

class StdioStreamBuf : public std::streambuf {
 public:
  explicit StdioStreamBuf(std::FILE* file) : file_(file) {}

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    return std::fputc(c, file_) == EOF ? traits_type::eof() : c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return static_cast<std::streamsize>(std::fwrite(s, 1, static_cast<size_t>(n), file_));
  }
  int sync() override { return std::fflush(file_) == 0 ? 0 : -1; }

 private:
  std::FILE* file_;
};

}  // namespace sb
