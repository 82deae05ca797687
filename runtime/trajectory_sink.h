#pragma once
// Streams the final poses as a TUM trajectory (core/trajectory.h format), one line per frame written as the
// frame ends (LineFile: a crash loses at most the frame in hand; a failed write throws), and keeps them in
// memory for evaluation.

#include <string>

#include "core/trajectory.h"
#include "runtime/line_file.h"
#include "runtime/output_sink.h"

namespace sb {

class TrajectorySink final : public OutputSink {
 public:
  // Creates (truncates) `path` and writes the header and `comment`. Throws sb::Error if it cannot.
  TrajectorySink(const std::string& path, const std::string& comment);
  void onFrame(const FrameRecord& record) override;
  void flush() override;
  const Trajectory& trajectory() const { return trajectory_; }

 private:
  LineFile out_;
  Trajectory trajectory_;
};

}  // namespace sb
