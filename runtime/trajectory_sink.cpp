#include "runtime/trajectory_sink.h"

namespace sb {

TrajectorySink::TrajectorySink(const std::string& path, const std::string& comment)
    : out_(path, "trajectory") {
  std::string header = "# timestamp tx ty tz qx qy qz qw\n";
  if (!comment.empty()) header += "# " + comment + "\n";
  out_.append(header);
}

void TrajectorySink::onFrame(const FrameRecord& record) {
  if (!record.hasPoseEstimate()) return;
  const TimedPose pose{record.result.timestamp, record.result.T_camera_to_world};
  out_.append(formatTumLine(pose) + "\n");
  trajectory_.push_back(pose);
}

void TrajectorySink::flush() {}  // every line is written as its frame ends

}  // namespace sb
