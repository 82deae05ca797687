#include "power/serial_port.h"

#include <fcntl.h>
#include <termios.h>

#include <cerrno>
#include <cstring>

namespace sb::power {

namespace {

bool baudToSpeed(int baud, speed_t& speed) {
  switch (baud) {
    case 9600: speed = B9600; return true;
    case 19200: speed = B19200; return true;
    case 38400: speed = B38400; return true;
    case 57600: speed = B57600; return true;
    case 115200: speed = B115200; return true;
    case 230400: speed = B230400; return true;
    case 460800: speed = B460800; return true;
    case 500000: speed = B500000; return true;
    case 576000: speed = B576000; return true;
    case 921600: speed = B921600; return true;
    default: return false;
  }
}

SerialOpenResult failure(const std::string& path, const char* call, int errnum) {
  SerialOpenResult r;
  r.errnum = errnum;
  r.error = "serial port '" + path + "': " + call + ": " + std::strerror(errnum);
  if (errnum == ENOENT || errnum == ENODEV || errnum == ENXIO)
    r.error += " (is the meter plugged in? look for it with 'ls /dev/ttyUSB* /dev/serial/by-id/')";
  else if (errnum == EACCES || errnum == EPERM)
    r.error += " (add the user to the 'dialout' group: sudo usermod -aG dialout $USER, then log in again)";
  else if (errnum == EBUSY)
    r.error += " (another program holds the port; close it)";
  return r;
}

}  // namespace

bool isSupportedBaud(int baud) {
  speed_t speed;
  return baudToSpeed(baud, speed);
}

SerialOpenResult openSerialPort(const std::string& path, int baud) {
  speed_t speed{};
  if (!baudToSpeed(baud, speed)) {
    SerialOpenResult r;
    r.errnum = EINVAL;
    r.error = "serial port '" + path + "': baud rate " + std::to_string(baud) + " is not supported";
    return r;
  }
  UniqueFd fd(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) return failure(path, "open", errno);
  termios tio{};
  if (tcgetattr(fd.get(), &tio) != 0) return failure(path, "tcgetattr (not a terminal?)", errno);
  cfmakeraw(&tio);  // no echo, no canonical mode, no CR/LF translation, 8 data bits, no parity
  tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS | HUPCL);  // 1 stop bit, no flow control
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  // VMIN 1 with O_NONBLOCK: read() fails with EAGAIN when there is nothing to read, so that 0 means hang-up
  // (with VMIN 0 and VTIME 0 an empty read would also return 0 and look like an unplugged device).
  tio.c_cc[VMIN] = 1;
  tio.c_cc[VTIME] = 0;
  if (cfsetispeed(&tio, speed) != 0 || cfsetospeed(&tio, speed) != 0) return failure(path, "cfsetspeed", errno);
  if (tcsetattr(fd.get(), TCSANOW, &tio) != 0) return failure(path, "tcsetattr", errno);
  tcflush(fd.get(), TCIFLUSH);  // stale bytes from before the open: the next line is likely partial anyway
  SerialOpenResult r;
  r.fd = std::move(fd);
  return r;
}

}  // namespace sb::power
