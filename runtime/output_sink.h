#pragma once
// An output of a run (trajectory, per-frame log, summary, ...). The runner hands every frame to each sink
// in order; flush() puts everything so far on disk and may be called at any time (the daemon calls it on
// SIGTERM and periodically). Sinks throw sb::Error naming the file when they cannot write.

#include "runtime/frame_record.h"

namespace sb {

class OutputSink {
 public:
  virtual ~OutputSink() = default;
  virtual void onFrame(const FrameRecord& record) = 0;
  virtual void flush() = 0;
};

}  // namespace sb
