#pragma once
// The client library (sb_client): the client's side of slamboosterd's socket (docs/protocol.md): connect,
// read the VERSION greeting, send request lines, read reply and report lines (with a timeout). Used by
// slamboosterctl and the tests; it needs neither the daemon's code nor libsystemd.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/unique_fd.h"

namespace sb::client {

// A blocking connection to the Unix stream socket at `path`. Throws sb::Error naming the path and what to
// check (is slamboosterd running? are you in the socket's group?).
UniqueFd connectUnix(const std::string& path);

class Connection {
 public:
  // Connects and reads the VERSION greeting. Throws sb::Error naming the path and what to check.
  explicit Connection(const std::string& socketPath, double timeoutSeconds);
  const nlohmann::json& version() const { return version_; }

  void send(const std::string& requestLine);
  // The next message; nullopt when the daemon closed the connection. Throws sb::Error on a timeout
  // (timeoutSeconds <= 0: wait forever) or on a line that is not a JSON object.
  std::optional<nlohmann::json> next(double timeoutSeconds);
  // Like next(), but a timeout is not an error: `timedOut` says whether nothing arrived within timeoutSeconds
  // (> 0). For long-lived clients that must do other work while they wait (the ROS bridge).
  std::optional<nlohmann::json> next(double timeoutSeconds, bool& timedOut);
  // The next message of class `cls`, or an ERROR (returned as it is), skipping streamed reports.
  nlohmann::json reply(const std::string& cls, double timeoutSeconds);

 private:
  UniqueFd fd_;
  std::string buffer_;
  nlohmann::json version_;
};

}  // namespace sb::client
