#!/usr/bin/env bash
# 64-bit time of ELF binaries (issue 34): on a 32-bit target, a binary built without -D_TIME_BITS=64 calls the
# C library's 32-bit time interfaces, whose seconds end on 2038-01-19 (file times, CLOCK_REALTIME stamps, the
# age order of rotated segments). Built with it, glibc (2.34 and later) redirects every call that takes or
# returns a time to its 64-bit twin: clock_gettime -> __clock_gettime64, stat64 -> __stat64_time64,
# getrusage -> __getrusage64, setsockopt -> __setsockopt64, ... (measured on Debian 12 armhf:
# docs/running-for-weeks.md). Debian 12's armhf libraries other than glibc keep a 32-bit time_t, so a binary
# built so must not call a library function whose interface carries a time_t or a struct timeval/timespec
# (the two sides would disagree on its layout): libusb's event calls with a timeout, png_convert_from_time_t.
# This lists the undefined dynamic symbols of each binary and fails for either kind.
#
#   tests/packaging/check_time64.sh [--all-classes] BINARY...
#
# 64-bit binaries (ELFCLASS64) have a 64-bit time_t whatever the flags and are passed over for the first kind,
# unless --all-classes asks to check them too. Exits 1 when a check fails, 2 on bad use.
set -uo pipefail

all_classes=0
if [ "${1:-}" = --all-classes ]; then all_classes=1; shift; fi
[ $# -gt 0 ] || { echo "usage: check_time64.sh [--all-classes] BINARY..." >&2; exit 2; }
command -v readelf >/dev/null || { echo "check_time64: readelf is missing (binutils)" >&2; exit 2; }

# glibc's 32-bit time interfaces that _TIME_BITS=64 redirects (each has a 64-bit twin).
time32_calls='time stime clock_gettime clock_settime clock_getres clock_nanosleep clock_adjtime gettimeofday
settimeofday adjtime adjtimex ntp_adjtime ntp_gettime ntp_gettimex nanosleep timespec_get timespec_getres
localtime localtime_r gmtime gmtime_r mktime timegm timelocal ctime ctime_r difftime stat64 lstat64 fstat64
fstatat64 __xstat64 __lxstat64 __fxstat64 __fxstatat64 fcntl64 ioctl utime utimes lutimes futimes futimesat
futimens utimensat timerfd_settime timerfd_gettime timer_settime timer_gettime getitimer setitimer select
pselect ppoll epoll_pwait2 pthread_cond_timedwait pthread_cond_clockwait pthread_mutex_timedlock
pthread_mutex_clocklock pthread_rwlock_timedrdlock pthread_rwlock_timedwrlock pthread_rwlock_clockrdlock
pthread_rwlock_clockwrlock pthread_timedjoin_np pthread_clockjoin_np sem_timedwait sem_clockwait
sched_rr_get_interval sigtimedwait mq_timedreceive mq_timedsend semtimedop aio_suspend getrusage wait3 wait4
setsockopt getsockopt recvmsg sendmsg recvmmsg sendmmsg msgctl semctl shmctl'
# Library functions of Debian 12 whose interface carries a time_t or struct timeval (found by scanning the
# installed headers of every library the package links: libusb-1.0, libpng, zlib, libsystemd, OpenNI2,
# OpenCL; the C++ libraries' time_t parameters are in their mangled names, so a mismatch fails to link).
library_time_calls='libusb_wait_for_event libusb_handle_events_timeout libusb_handle_events_timeout_completed
libusb_handle_events_locked libusb_get_next_timeout png_convert_from_time_t'

listed() { tr ' ' '\n' <<<"$1" | sed '/^$/d' | sort -u; }
failed=0
for bin in "$@"; do
  [ -f "$bin" ] || { echo "check_time64: no such file: $bin" >&2; exit 2; }
  class=$(readelf -h "$bin" 2>/dev/null | sed -n 's/^ *Class: *//p')
  [ -n "$class" ] || { echo "check_time64: $bin is not an ELF file" >&2; exit 2; }
  undefined=$(readelf -W --dyn-syms --syms "$bin" 2>/dev/null | awk '$7 == "UND" && $8 != "" {print $8}' |
    sed 's/@.*//' | sort -u)
  bad_lib=$(comm -12 <(listed "$library_time_calls") <(echo "$undefined"))
  if [ -n "$bad_lib" ]; then
    echo "FAIL: $bin ($class) calls library functions whose time_t/timeval differs from a _TIME_BITS=64 build's" \
      "on Debian 12 armhf: $(echo $bad_lib)"
    failed=1
  fi
  if [ "$class" != ELF32 ] && [ "$all_classes" = 0 ]; then
    [ -n "$bad_lib" ] || echo "check_time64: $bin: $class, 64-bit time always"
    continue
  fi
  bad=$(comm -12 <(listed "$time32_calls") <(echo "$undefined"))
  if [ -n "$bad" ]; then
    echo "FAIL: $bin ($class) calls 32-bit time interfaces (built without -D_TIME_BITS=64): $(echo $bad)"
    failed=1
  elif [ -z "$bad_lib" ]; then
    echo "check_time64: $bin ($class): 64-bit time"
  fi
done
exit $failed
