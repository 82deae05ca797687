#include "tests/power/pty_simulator.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace sb::test {

PtySimulator::PtySimulator(std::string linkPath) : link_(std::move(linkPath)) { open(); }

PtySimulator::~PtySimulator() {
  close();
  ::unlink(link_.c_str());
}

void PtySimulator::open() {
  char name[128] = {};
  if (openpty(&master_, &slave_, name, nullptr, nullptr) != 0) throw std::runtime_error("openpty failed");
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);  // no echo back into the master, no CR/LF mapping before the driver configures it
  tcsetattr(slave_, TCSANOW, &tio);
  const std::string temporary = link_ + ".new";
  ::unlink(temporary.c_str());
  if (::symlink(name, temporary.c_str()) != 0 || ::rename(temporary.c_str(), link_.c_str()) != 0)
    throw std::runtime_error("cannot link " + link_ + " to " + name);
}

void PtySimulator::close() {
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
  slave_ = master_ = -1;
}

void PtySimulator::write(std::string_view bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
    if (n <= 0) throw std::runtime_error("write to pty master failed");
    done += static_cast<size_t>(n);
  }
}

void PtySimulator::unplug() { close(); }

void PtySimulator::replug() {
  close();
  open();
}

bool pollUntil(power::Meter& meter, std::vector<power::PowerSample>& out, size_t count, int timeoutMs) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  for (;;) {
    meter.poll(out);
    if (out.size() >= count) return true;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{meter.waitFd(), POLLIN, 0};
    if (p.fd >= 0) ::poll(&p, 1, static_cast<int>(std::min<long>(left.count(), 50)));
    else ::usleep(1000);
  }
}

void settle(power::Meter& meter) {
  pollfd p{meter.waitFd(), POLLIN, 0};
  ::poll(&p, 1, 1000);
  ::usleep(20000);
}

void pollFor(power::Meter& meter, std::vector<power::PowerSample>& out, int waitMs) {
  pollUntil(meter, out, out.size() + 1000000, waitMs);
}

}  // namespace sb::test
