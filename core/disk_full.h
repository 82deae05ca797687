#pragma once
// A write that failed because the file system is full (ENOSPC) or the quota is spent (EDQUOT). The retention
// of rotated outputs (core/segment_store.h: SegmentStore::writeMakingRoom) catches it, removes the oldest
// segment and writes again; anywhere else it is an sb::Error like any other.

#include "core/error.h"

namespace sb {

class DiskFullError : public Error {
 public:
  using Error::Error;
};

}  // namespace sb
