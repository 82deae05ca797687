#include "daemon/peer_auth.h"

#include <grp.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace sb::daemon {

PeerCredentials peerCredentials(int fd) {
  ucred cred{};
  socklen_t len = sizeof cred;
  if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0)
    throw Error(std::string("SO_PEERCRED failed: ") + std::strerror(errno));
  PeerCredentials p;
  p.pid = cred.pid;
  p.uid = cred.uid;
  p.gid = cred.gid;
#ifdef SO_PEERGROUPS
  std::vector<gid_t> groups(64);
  for (int attempt = 0; attempt < 4; ++attempt) {
    socklen_t bytes = static_cast<socklen_t>(groups.size() * sizeof(gid_t));
    if (getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &bytes) == 0) {
      groups.resize(bytes / sizeof(gid_t));
      p.groups = std::move(groups);
      break;
    }
    if (errno != ERANGE) break;  // older kernel: only the primary gid is known
    groups.resize(bytes / sizeof(gid_t) + 1);
  }
#endif
  return p;
}

ControlPolicy::ControlPolicy(uid_t daemonUid, const std::string& groupSpec)
    : daemonUid_(daemonUid), groupName_(groupSpec) {
  const std::string& name = groupSpec;
  if (name.empty()) return;
  if (name.find_first_not_of("0123456789") == std::string::npos) {
    group_ = static_cast<gid_t>(std::stoul(name));
    return;
  }
  errno = 0;
  const struct group* g = getgrnam(name.c_str());
  if (!g)
    throw Error("socket.control_group = \"" + name + "\": no such group (create it with `groupadd " + name +
                "` or leave the key empty)");
  group_ = g->gr_gid;
}

bool ControlPolicy::allowed(const PeerCredentials& peer) const {
  if (peer.uid == 0 || peer.uid == daemonUid_) return true;
  if (!group_) return false;
  return peer.gid == *group_ ||
         std::find(peer.groups.begin(), peer.groups.end(), *group_) != peer.groups.end();
}

std::string ControlPolicy::describe() const {
  std::string s = "root or uid " + std::to_string(daemonUid_);
  if (group_) s += " or members of group '" + groupName_ + "'";
  return s;
}

}  // namespace sb::daemon
