#pragma once
// The daemon's file-descriptor budget: every client holds one descriptor, and the pipeline needs its own
// (frames being read, outputs, meters, epoll/signal/timer fds, GPU driver files). At start the soft
// RLIMIT_NOFILE is raised as far as needed (up to the hard limit); when socket.max_clients plus the reserve
// still does not fit, start-up fails with a ConfigError that says which number to change.

#include <cstddef>

namespace sb::daemon {

// Descriptors kept for the pipeline and the daemon itself, beyond one per client (and one for a refused
// client in flight). A replay on the cpu backend without a meter holds 12 (measured: stdio, epoll, signal,
// timer and event fds, the listener, trajectory and per-frame log); a meter, a camera or an OpenCL driver
// add a few; the rest is headroom.
inline constexpr size_t kReservedFds = 64;

// Descriptors needed for `maxClients` clients.
inline size_t fdsNeeded(size_t maxClients) {
  return maxClients + 1 + kReservedFds;
}

// Raises the soft RLIMIT_NOFILE to fdsNeeded(maxClients) when lower (never above the hard limit). Throws
// ConfigError naming socket.max_clients, the limit and LimitNOFILE= when it cannot. Returns the soft limit.
size_t ensureFdBudget(size_t maxClients);

}  // namespace sb::daemon
