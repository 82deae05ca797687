#include "core/json_text.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"
#include "core/input_file.h"
#include "core/unique_fd.h"

namespace sb {

namespace {

// "line L, column C" of the byte at `offset` (0-based) in `text`.
std::string position(std::string_view text, size_t offset) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Offset of the first '[' or '{' (outside strings) that opens level maxDepth + 1, or npos.
size_t tooDeepAt(std::string_view text, int maxDepth) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (inString) {
      if (escaped)
        escaped = false;
      else if (ch == '\\')
        escaped = true;
      else if (ch == '"')
        inString = false;
    } else if (ch == '"') {
      inString = true;
    } else if (ch == '[' || ch == '{') {
      if (++depth > maxDepth) return i;
    } else if ((ch == ']' || ch == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

// Longest part of nlohmann's message kept: it quotes the last token read, which may be the whole input.
constexpr size_t kMaxMessageBytes = 160;

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1, column 2: " prefix,
// cut to kMaxMessageBytes.
std::string parseMessage(const nlohmann::json::parse_error& e) {
  const std::string what = e.what();
  const auto colon = what.find(": ");
  std::string message = colon == std::string::npos ? what : what.substr(colon + 2);
  if (message.size() > kMaxMessageBytes) message = message.substr(0, kMaxMessageBytes) + "...";
  return message;
}

}  // namespace

std::optional<nlohmann::json> tryParseJson(std::string_view text, std::string& error, int maxDepth) {
  const size_t deep = tooDeepAt(text, maxDepth);
  if (deep != std::string_view::npos) {
    error = "arrays and objects nest deeper than " + std::to_string(maxDepth) + " levels (at " +
            position(text, deep) + ")";
    return std::nullopt;
  }
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    const size_t at = e.byte > 0 ? e.byte - 1 : 0;
    error = "not valid JSON at " + position(text, at) + ": " + parseMessage(e);
  } catch (const nlohmann::json::exception& e) {
    error = std::string("not valid JSON: ") + std::string(e.what()).substr(0, kMaxMessageBytes);
  }
  return std::nullopt;
}

nlohmann::json parseJson(std::string_view text, const std::string& where, int maxDepth) {
  std::string error;
  auto j = tryParseJson(text, error, maxDepth);
  if (!j) throw Error(where + ": " + error);
  return std::move(*j);
}

std::string readTextFile(const std::string& path, const std::string& what, size_t maxBytes) {
  const std::string name = what + " " + quoteForMessage(path);
  UniqueFd fd = openRegularFile(path, what);  // never blocks: a FIFO, socket or device is refused first
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw Error("cannot read " + name + ": " + std::strerror(errno));
  if (static_cast<uint64_t>(st.st_size) > maxBytes)
    throw Error(name + " is " + std::to_string(st.st_size) + " bytes; settings files are at most " +
                std::to_string(maxBytes));
  std::string text;
  char buf[65536];
  while (true) {
    const ssize_t n = ::read(fd.get(), buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error("cannot read " + name + ": " + std::strerror(errno));
    if (n == 0) break;
    text.append(buf, static_cast<size_t>(n));
    if (text.size() > maxBytes)
      throw Error(name + " is longer than " + std::to_string(maxBytes) +
                  " bytes (the limit for settings files)");
  }
  return text;
}

std::string describeJson(const nlohmann::json& value, size_t maxChars) {
  if (value.is_array()) return "an array of " + std::to_string(value.size()) + " elements";
  if (value.is_object()) return "an object with " + std::to_string(value.size()) + " keys";
  if (value.is_discarded()) return "nothing";
  std::string s = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (s.size() > maxChars) s = s.substr(0, maxChars) + "...";
  return s;
}

}  // namespace sb
