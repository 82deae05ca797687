#include "daemon/fd_budget.h"

#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "daemon/daemon_config.h"

namespace sb::daemon {

size_t ensureFdBudget(size_t maxClients) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0)
    throw Error(std::string("getrlimit(RLIMIT_NOFILE) failed: ") + std::strerror(errno));
  const rlim_t needed = static_cast<rlim_t>(fdsNeeded(maxClients));
  if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur < needed) {
    rlimit raised = limit;
    raised.rlim_cur = (limit.rlim_max == RLIM_INFINITY || limit.rlim_max >= needed) ? needed : limit.rlim_max;
    if (setrlimit(RLIMIT_NOFILE, &raised) == 0) limit = raised;
  }
  if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur < needed) {
    const size_t fits = limit.rlim_cur > kReservedFds + 1 ? limit.rlim_cur - kReservedFds - 1 : 0;
    throw ConfigError(
        "socket.max_clients = " + std::to_string(maxClients) + " needs " + std::to_string(needed) +
        " open files (one per client plus " + std::to_string(kReservedFds + 1) +
        " for the pipeline), but RLIMIT_NOFILE is " + std::to_string(limit.rlim_cur) + " (hard " +
        (limit.rlim_max == RLIM_INFINITY ? std::string("unlimited") : std::to_string(limit.rlim_max)) +
        "); " +
        (fits > 0 ? "set socket.max_clients to at most " + std::to_string(fits) + " or raise the limit"
                  : std::string("raise the limit")) +
        " (LimitNOFILE= in the unit, ulimit -n)");
  }
  return limit.rlim_cur == RLIM_INFINITY ? static_cast<size_t>(-1) : static_cast<size_t>(limit.rlim_cur);
}

}  // namespace sb::daemon
