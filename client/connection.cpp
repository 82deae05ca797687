#include "client/connection.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "core/error.h"
#include "core/json_text.h"
#include "core/unix_address.h"

namespace sb::client {

UniqueFd connectUnix(const std::string& path) {
  const sockaddr_un addr = unixSocketAddress(path);
  UniqueFd fd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd.valid()) throw Error(std::string("socket(AF_UNIX) failed: ") + std::strerror(errno));
  if (connect(fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    throw Error("cannot connect to '" + path + "': " + std::strerror(errno) +
                (errno == ENOENT || errno == ECONNREFUSED ? " (is slamboosterd running?)"
                 : errno == EACCES                        ? " (are you in the socket's group?)"
                                                          : ""));
  return fd;
}

Connection::Connection(const std::string& socketPath, double timeoutSeconds) : fd_(connectUnix(socketPath)) {
  auto greeting = next(timeoutSeconds);
  const auto field = [&](const char* key) {
    const auto it = greeting->find(key);
    return it != greeting->end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  // A full daemon greets with ERROR ("too many clients ...") and closes: say that, not "no VERSION".
  if (greeting && field("class") == "ERROR")
    throw Error("slamboosterd at '" + socketPath + "' refused the connection: " + field("message"));
  if (!greeting || field("class") != "VERSION")
    throw Error("'" + socketPath + "' did not greet with VERSION: is it a slamboosterd socket?");
  version_ = *greeting;
}

void Connection::send(const std::string& requestLine) {
  const std::string bytes = requestLine + "\n";
  size_t off = 0;
  while (off < bytes.size()) {
    const ssize_t n = ::send(fd_.get(), bytes.data() + off, bytes.size() - off, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(std::string("cannot send to slamboosterd: ") + std::strerror(errno));
    off += static_cast<size_t>(n);
  }
}

std::optional<nlohmann::json> Connection::next(double timeoutSeconds) {
  bool timedOut = false;
  auto message = next(timeoutSeconds, timedOut);
  if (timedOut) throw Error("no reply from slamboosterd within " + std::to_string(timeoutSeconds) + " s");
  return message;
}

std::optional<nlohmann::json> Connection::next(double timeoutSeconds, bool& timedOut) {
  timedOut = false;
  using Clock = std::chrono::steady_clock;
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(timeoutSeconds > 0 ? timeoutSeconds : 0));
  while (true) {
    const auto nl = buffer_.find('\n');
    if (nl != std::string::npos) {
      const std::string line = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      std::string error;
      auto j = tryParseJson(line, error);
      if (!j || !j->is_object())
        throw Error("slamboosterd sent a line that is not a JSON object: " + line.substr(0, 200));
      return std::move(*j);
    }
    int waitMs = -1;
    if (timeoutSeconds > 0) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        timedOut = true;
        return std::nullopt;
      }
      waitMs = static_cast<int>(left);
    }
    pollfd p{fd_.get(), POLLIN, 0};
    const int r = ::poll(&p, 1, waitMs);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) throw Error(std::string("poll failed: ") + std::strerror(errno));
    if (r == 0) continue;  // the deadline check above reports it
    char buf[65536];
    const ssize_t n = ::recv(fd_.get(), buf, sizeof buf, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return std::nullopt;
    buffer_.append(buf, static_cast<size_t>(n));
  }
}

nlohmann::json Connection::reply(const std::string& cls, double timeoutSeconds) {
  while (true) {
    auto m = next(timeoutSeconds);
    if (!m) throw Error("slamboosterd closed the connection before replying");
    const std::string c = m->value("class", "");
    if (c == cls || c == "ERROR") return *m;
  }
}

}  // namespace sb::client
