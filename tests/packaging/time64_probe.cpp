// A probe of glibc's 64-bit time interfaces on a 32-bit target (issue 34; docs/running-for-weeks.md): calls
// every time-carrying interface the project uses or might, so that the symbols it imports show what
// -D_TIME_BITS=64 redirects. Not built by the project; cross-compile it twice and compare:
//
//   arm-linux-gnueabihf-g++ -std=c++17 -O1 -D_FILE_OFFSET_BITS=64 time64_probe.cpp -o probe32
//   arm-linux-gnueabihf-g++ -std=c++17 -O1 -D_FILE_OFFSET_BITS=64 -D_TIME_BITS=64 time64_probe.cpp -o probe64
//   tests/packaging/check_time64.sh probe32 probe64   # probe32 fails (clock_gettime, stat64, ...), probe64 passes
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <sys/ioctl.h>
#include <sys/select.h>
#include <poll.h>
#include <fcntl.h>
#include <time.h>
#include <pthread.h>
#include <semaphore.h>
#include <unistd.h>
#include <utime.h>
#include <sys/wait.h>
int main() {
  timespec ts{}; clock_gettime(CLOCK_MONOTONIC, &ts); clock_getres(CLOCK_MONOTONIC, &ts); nanosleep(&ts, nullptr);
  clock_nanosleep(CLOCK_MONOTONIC, 0, &ts, nullptr);
  time_t t = time(nullptr); tm m{}; localtime_r(&t, &m); gmtime_r(&t, &m); t = mktime(&m); t = timegm(&m);
  timeval tv{}; gettimeofday(&tv, nullptr);
  struct stat st{}; stat("/", &st); fstat(0, &st); lstat("/", &st); fstatat(0, "x", &st, 0);
  rusage ru{}; getrusage(RUSAGE_SELF, &ru); wait4(-1, nullptr, WNOHANG, &ru);
  setsockopt(0, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv); socklen_t l = sizeof tv; getsockopt(0, SOL_SOCKET, SO_RCVTIMEO, &tv, &l);
  msghdr mh{}; recvmsg(0, &mh, 0); sendmsg(0, &mh, 0);
  itimerspec its{}; timerfd_settime(0, 0, &its, nullptr); timerfd_gettime(0, &its);
  fd_set fds; FD_ZERO(&fds); select(1, &fds, nullptr, nullptr, &tv); pollfd p{}; ppoll(&p, 1, &ts, nullptr);
  ioctl(0, 0); fcntl(0, F_GETFL);
  pthread_cond_t c = PTHREAD_COND_INITIALIZER; pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
  pthread_cond_timedwait(&c, &mu, &ts); pthread_cond_clockwait(&c, &mu, CLOCK_MONOTONIC, &ts); pthread_mutex_timedlock(&mu, &ts);
  sem_t s; sem_timedwait(&s, &ts);
  timespec times[2]{}; utimensat(0, "x", times, 0); futimens(0, times); utime("x", nullptr);
  return 0;
}
