// libFuzzer target for the socket request parser: any bytes in, never a crash, a hang or a sanitizer report;
// every refusal has a message that encodes as a valid ERROR line.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "daemon/protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const sb::daemon::ParseResult r = sb::daemon::parseRequest(line);
  if (r.request.has_value() == !r.error.empty()) std::abort();  // exactly one of request and error
  if (!r.request) {
    const std::string encoded = sb::daemon::toLine(sb::daemon::errorMessage(r.error));
    if (encoded.empty() || encoded.back() != '\n' || encoded.find('\n') != encoded.size() - 1) std::abort();
    if (!nlohmann::json::accept(encoded)) std::abort();
  }
  return 0;
}
