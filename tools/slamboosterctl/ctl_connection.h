#pragma once
// slamboosterctl's side of the socket: connect, send one request line, read reply lines (with a timeout).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/unique_fd.h"

namespace sb::ctl {

class Connection {
 public:
  // Connects and reads the VERSION greeting. Throws sb::Error naming the path and what to check.
  explicit Connection(const std::string& socketPath, double timeoutSeconds);
  const nlohmann::json& version() const { return version_; }

  void send(const std::string& requestLine);
  // The next message; nullopt when the daemon closed the connection. Throws sb::Error on a timeout
  // (timeoutSeconds <= 0: wait forever) or on a line that is not a JSON object.
  std::optional<nlohmann::json> next(double timeoutSeconds);
  // The next message of class `cls`, or an ERROR (returned as it is), skipping streamed reports.
  nlohmann::json reply(const std::string& cls, double timeoutSeconds);

 private:
  UniqueFd fd_;
  std::string buffer_;
  nlohmann::json version_;
};

}  // namespace sb::ctl
