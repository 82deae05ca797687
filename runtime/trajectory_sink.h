#pragma once
// Streams the final poses as a TUM trajectory (core/trajectory.h format), one line per frame, and keeps
// them in memory for evaluation.

#include <fstream>
#include <string>

#include "core/trajectory.h"
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
  std::string path_;
  std::ofstream out_;
  Trajectory trajectory_;
};

}  // namespace sb
