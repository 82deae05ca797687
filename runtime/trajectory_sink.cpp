#include "runtime/trajectory_sink.h"

namespace sb {

namespace {

std::string header(const std::string& comment) {
  std::string h = "# timestamp tx ty tz qx qy qz qw\n";
  if (!comment.empty()) h += "# " + comment + "\n";
  return h;
}

}  // namespace

TrajectorySink::TrajectorySink(const std::string& dir, const std::string& comment,
                               std::shared_ptr<SegmentStore> segments)
    : out_(dir, "trajectory.tum", "trajectory", header(comment), std::move(segments)) {}

void TrajectorySink::onFrame(const FrameRecord& record) {
  if (!record.hasPoseEstimate()) return;
  out_.append(formatTumLine(TimedPose{record.result.timestamp, record.result.T_camera_to_world}) + "\n");
}

void TrajectorySink::flush() {}  // every line is written as its frame ends

Trajectory TrajectorySink::readBack() const {
  Trajectory all;
  for (const std::string& file : out_.files()) {
    Trajectory part = readTumTrajectory(file);
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}

}  // namespace sb
