#include "tools/slambooster/claim.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "core/input_file.h"

namespace sb::cli {

namespace {

std::string hostName() {
  char buffer[256] = {};
  gethostname(buffer, sizeof(buffer) - 1);
  return buffer;
}

std::string readOwner(const std::string& path) {
  std::string owner;
  std::unique_ptr<InputFile> file;
  try {  // missing (released meanwhile), or not a regular file: no owner (never blocks on a FIFO)
    file = std::make_unique<InputFile>(path, "claim file");
  } catch (const Error&) {
    return owner;
  }
  std::istream& in = *file;
  std::getline(in, owner);
  return owner;
}

// Seconds since the file was last modified (a negative age, from a clock ahead, counts as fresh).
double ageS(const struct stat& st) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const double nowS = std::chrono::duration<double>(now).count();
  return nowS - (double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec));
}

// Stale: the owner process is gone (same host) or the heartbeat stopped longer than the lease ago.
bool stale(const std::string& owner, const struct stat& st) {
  std::istringstream words(owner);
  std::string host;
  long pid = 0;
  words >> host >> pid;
  if (host == hostName() && pid > 0 && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return true;
  return ageS(st) > kClaimLeaseS;
}

}  // namespace

std::string claimOwner() { return hostName() + " " + std::to_string(getpid()); }

bool claimJob(const std::string& dir) {
  const std::string path = dir + "/.claim";
  const std::string aside = path + ".stale." + hostName() + "." + std::to_string(getpid());
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int fd = open(path.c_str(), O_CREAT | O_EXCL | O_WRONLY, 0644);
    if (fd >= 0) {
      const std::string line = claimOwner() + "\n";
      const bool written = write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
      close(fd);
      if (written) return true;
      unlink(path.c_str());
      return false;
    }
    struct stat st {};
    if (stat(path.c_str(), &st) != 0) continue;  // let go of meanwhile: try again
    const std::string owner = readOwner(path);
    if (!stale(owner, st)) return false;
    // Take it over: rename it aside (of several takers, one moves it), then check that what was moved is
    // the stale claim and not a fresh one made between the look and the rename.
    if (rename(path.c_str(), aside.c_str()) != 0) continue;
    struct stat moved {};
    const bool same = stat(aside.c_str(), &moved) == 0 && readOwner(aside) == owner && stale(owner, moved);
    if (!same) {
      // A fresh claim, made between the look and the rename, was moved: put it back (unless yet another
      // claim appeared meanwhile; the job has an owner either way).
      (void)!link(aside.c_str(), path.c_str());
      unlink(aside.c_str());
      return false;
    }
    unlink(aside.c_str());
  }
  return false;
}

void refreshClaim(const std::string& dir) {
  const std::string path = dir + "/.claim";
  if (readOwner(path) == claimOwner()) utimensat(AT_FDCWD, path.c_str(), nullptr, 0);
}

void releaseClaim(const std::string& dir) {
  const std::string path = dir + "/.claim";
  if (readOwner(path) == claimOwner()) unlink(path.c_str());
}

}  // namespace sb::cli
