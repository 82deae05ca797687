#pragma once
// Who is on the other end of a Unix socket (SO_PEERCRED, SO_PEERGROUPS), and whether they may send
// privileged requests (?CONTROL): root, the daemon's own user, or a member of the configured group.

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace sb::daemon {

struct PeerCredentials {
  pid_t pid = 0;
  uid_t uid = static_cast<uid_t>(-1);
  gid_t gid = static_cast<gid_t>(-1);
  std::vector<gid_t> groups;  // supplementary groups (empty when the kernel cannot tell)
};

// Reads the credentials of the peer of a connected Unix stream socket. Throws sb::Error.
PeerCredentials peerCredentials(int fd);

class ControlPolicy {
 public:
  // `group`: a group name or numeric gid; empty = no group. Throws sb::Error naming an unknown group.
  ControlPolicy(uid_t daemonUid, const std::string& groupSpec);
  bool allowed(const PeerCredentials& peer) const;
  // For the ERROR reply: who may control.
  std::string describe() const;

 private:
  uid_t daemonUid_;
  std::optional<gid_t> group_;
  std::string groupName_;
};

}  // namespace sb::daemon
