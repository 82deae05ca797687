#pragma once
// The listening Unix stream socket: either handed over by systemd (socket activation, LISTEN_FDS) or
// created at the configured path with the configured mode.

#include <string>

#include "core/unique_fd.h"

namespace sb::daemon {

struct ListeningSocket {
  UniqueFd fd;
  std::string path;        // where clients connect
  bool activated = false;  // from systemd (LISTEN_FDS): the daemon neither creates nor removes the file
  ~ListeningSocket();      // removes the socket file the daemon created
  ListeningSocket() = default;
  ListeningSocket(ListeningSocket&&) = default;
  ListeningSocket& operator=(ListeningSocket&&) = default;
};

// Takes the socket systemd passed (exactly one Unix stream socket), or binds `path` with permission bits
// `mode`. A stale socket file left by a dead daemon is replaced; a live one is an error. Throws sb::Error
// naming the path and what to do.
ListeningSocket openListeningSocket(const std::string& path, unsigned mode);

// The same without socket activation: always binds `path` (for a second socket, e.g. the push source's).
// `key` is the configuration key that sets `path`, named in errors.
ListeningSocket bindListeningSocket(const std::string& path, unsigned mode, const std::string& key = "socket.path");

// The client's side (connectUnix) is in the client library, client/connection.h.

}  // namespace sb::daemon
