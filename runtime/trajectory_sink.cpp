#include "runtime/trajectory_sink.h"

#include "core/error.h"

namespace sb {

TrajectorySink::TrajectorySink(const std::string& path, const std::string& comment) : path_(path), out_(path) {
  if (!out_) throw Error("cannot write trajectory '" + path + "' (check the output directory)");
  out_ << "# timestamp tx ty tz qx qy qz qw\n";
  if (!comment.empty()) out_ << "# " << comment << "\n";
}

void TrajectorySink::onFrame(const FrameRecord& record) {
  const TimedPose pose{record.result.timestamp, record.result.T_camera_to_world};
  trajectory_.push_back(pose);
  out_ << formatTumLine(pose) << "\n";
}

void TrajectorySink::flush() {
  out_.flush();
  if (!out_) throw Error("writing trajectory '" + path_ + "' failed (disk full?)");
}

}  // namespace sb
