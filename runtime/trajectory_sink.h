#pragma once
// Streams the final poses as a TUM trajectory (core/trajectory.h format), one line per frame written as the
// frame ends (RotatingFile: a crash loses at most the frame in hand; a failed write throws). Nothing is kept
// in memory: whatever needs the whole trajectory reads it back (readBack()). With a segment store the file is
// rotated (trajectory-000001.tum, ..., each with the header; core/rotating_file.h).

#include <memory>
#include <string>

#include "core/rotating_file.h"
#include "core/trajectory.h"
#include "runtime/output_sink.h"

namespace sb {

class TrajectorySink final : public OutputSink {
 public:
  // Creates (truncates) DIR/trajectory.tum, or with `segments` its first new segment, and writes the header
  // and `comment`. Throws sb::Error if it cannot.
  TrajectorySink(const std::string& dir, const std::string& comment,
                 std::shared_ptr<SegmentStore> segments = nullptr);
  void onFrame(const FrameRecord& record) override;
  void flush() override;
  RotatingFile& file() { return out_; }
  // The poses written so far, read back from the files still on disk (retention may have removed the oldest
  // segments). Throws sb::Error naming a malformed file.
  Trajectory readBack() const;

 private:
  RotatingFile out_;
};

}  // namespace sb
