#pragma once
// Room kept aside on disk for a file's last write (issue 53 finding 8): when the disk fills, the last thing a
// run must still write is summary.json saying so, and a full disk refuses that write like any other. So a
// new file beside the target ("<target>.reserve.<random>", core/exclusive_file.h: never through a link) is
// made at the start with its room allocated (posix_fallocate: the blocks are the file's, no other writer can
// take them), and the target's last write goes into that room, the file then renamed over the target: whole
// or not at all, like every other rewrite of it. Unused, the file is removed when this object goes.
//
//   ReservedFile reserve(dir + "/summary.json", 16 << 10);  // throws when the disk cannot hold it now
//   ... a write of summary.json fails on a full disk:
//   reserve.replaceTarget(text);                            // written into the room kept, renamed over it
//
// On a file system that allocates on every write whatever was reserved (copy-on-write: btrfs, ZFS) the
// room is no guarantee; on tmpfs, ext4 and XFS it is.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace sb {

class TemporaryFile;

class ReservedFile {
 public:
  // Allocates `bytes` beside `target`. Throws sb::DiskFullError naming the target when the disk cannot hold
  // them now (sb::Error on any other failure).
  ReservedFile(const std::string& target, uint64_t bytes);
  ~ReservedFile();
  ReservedFile(const ReservedFile&) = delete;
  ReservedFile& operator=(const ReservedFile&) = delete;

  // The bytes kept aside; 0 once replaceTarget() ran.
  uint64_t bytes() const { return bytes_; }
  // Keeps at least `bytes` aside. Best effort: false (the room kept before stays) when the disk cannot hold
  // more now or the reserve was used.
  bool grow(uint64_t bytes);
  // Writes `content` into the room kept aside and renames the file over the target; once only (the room is
  // then gone). Content larger than the room needs that much more free. Throws sb::WriteError naming the
  // target (sb::DiskFullError when the disk is full); the target then keeps what it had.
  void replaceTarget(std::string_view content);

 private:
  std::string target_;
  std::unique_ptr<TemporaryFile> file_;
  uint64_t bytes_ = 0;
};

}  // namespace sb
