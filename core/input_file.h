#pragma once
// Reading a path that a user, a config or a sequence names, without ever blocking and with messages that say
// what is really there. A FIFO, socket or device where a file is expected is refused before a byte is read:
// the path is opened with O_NONBLOCK (so a FIFO's open returns at once) and checked with fstat. Messages say
// "is a named pipe (FIFO)", "is a directory", "is a symbolic-link loop", ... rather than "does not exist".

#include <cstddef>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>
#include <string_view>

#include "core/unique_fd.h"

namespace sb {

// What `path` is when it cannot be read as a regular file, as the end of a sentence ("does not exist",
// "is a directory", "is a named pipe (FIFO)", "is a character device", "is a socket", "is a symbolic-link
// loop", "cannot be reached: Permission denied (a directory on the way cannot be searched)", ...); empty when
// it is a readable regular file.
std::string pathProblem(const std::string& path);

// True when `path` is a regular file (after symlinks) that could be opened for reading.
bool isReadableRegularFile(const std::string& path);

// Opens a regular file for reading without blocking. Throws sb::Error "cannot open <what> '<path>': it
// <pathProblem> (...)" when it is anything else.
UniqueFd openRegularFile(const std::string& path, const std::string& what);

// A std::istream over openRegularFile(path, what): the ifstream of every text input (index files,
// trajectories, logs). Reading errors set badbit as an ifstream does.
class InputFile : public std::istream {
 public:
  InputFile(const std::string& path, const std::string& what);
  ~InputFile() override;

 private:
  std::unique_ptr<std::streambuf> buffer_;
};

// `text` fit for a terminal or a log line: control bytes (ESC, NUL, ...) written as \xNN, newlines and tabs
// kept, and cut to `maxBytes` (the middle removed, with the number of bytes cut said) when longer.
std::string printable(std::string_view text, size_t maxBytes = 4096);

// A path or value quoted in a message: '...' with control bytes escaped and at most `maxBytes` kept.
std::string quoteForMessage(std::string_view value, size_t maxBytes = 256);

}  // namespace sb
