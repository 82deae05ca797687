#!/usr/bin/env bash
# Large-file support of ELF binaries: on a 32-bit target, a binary built without -D_FILE_OFFSET_BITS=64 calls
# the 32-bit file interfaces of the C library (open, lseek, fopen, stat, ftruncate, pwrite, ...), whose offsets
# and sizes stop at 2 GiB: an output file that grows past it fails on every write. Built with it, the same
# calls go to open64, lseek64, ... This lists the undefined dynamic symbols of each binary and fails for any of
# those 32-bit interfaces (what lintian reports as binary-file-built-without-LFS-support).
#
#   tests/packaging/check_lfs.sh [--all-classes] BINARY...
#
# 64-bit binaries (ELFCLASS64) have 64-bit offsets whatever the flags and are passed over, unless
# --all-classes asks to list their 32-bit-named calls too (the test of this check: tests/packaging/CMakeLists).
# Exits 1 when a binary lacks large-file support, 2 on bad use.
set -uo pipefail

all_classes=0
if [ "${1:-}" = --all-classes ]; then all_classes=1; shift; fi
[ $# -gt 0 ] || { echo "usage: check_lfs.sh [--all-classes] BINARY..." >&2; exit 2; }
command -v readelf >/dev/null || { echo "check_lfs: readelf is missing (binutils)" >&2; exit 2; }

# The glibc calls that take or return file offsets or sizes, or structures holding them; each has a 64 twin.
lfs_calls='open openat creat fopen freopen tmpfile fseeko ftello fgetpos fsetpos lseek pread pwrite preadv
pwritev truncate ftruncate stat lstat fstat fstatat __xstat __lxstat __fxstat __fxstatat statfs fstatfs statvfs
fstatvfs readdir readdir_r scandir scandirat alphasort versionsort glob globfree ftw nftw mmap getrlimit
setrlimit prlimit posix_fadvise posix_fallocate fallocate sendfile lockf mkstemp mkostemp mkstemps mkostemps
fcntl getdirentries'

failed=0
for bin in "$@"; do
  [ -f "$bin" ] || { echo "check_lfs: no such file: $bin" >&2; exit 2; }
  class=$(readelf -h "$bin" 2>/dev/null | sed -n 's/^ *Class: *//p')
  [ -n "$class" ] || { echo "check_lfs: $bin is not an ELF file" >&2; exit 2; }
  if [ "$class" != ELF32 ] && [ "$all_classes" = 0 ]; then
    echo "check_lfs: $bin: $class, 64-bit offsets always"
    continue
  fi
  # Undefined symbols (dynamic ones of an executable or library; the symbol table of an object file), without
  # their version suffix.
  undefined=$(readelf -W --dyn-syms --syms "$bin" 2>/dev/null | awk '$7 == "UND" && $8 != "" {print $8}' |
    sed 's/@.*//' | sort -u)
  bad=$(comm -12 <(tr ' ' '\n' <<<"$lfs_calls" | sed '/^$/d' | sort -u) <(echo "$undefined"))
  if [ -n "$bad" ]; then
    echo "FAIL: $bin ($class) calls 32-bit file interfaces (built without -D_FILE_OFFSET_BITS=64): $(echo $bad)"
    failed=1
  else
    echo "check_lfs: $bin ($class): large-file support"
  fi
done
exit $failed
