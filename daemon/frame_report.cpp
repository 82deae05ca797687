#include "daemon/frame_report.h"

#include "runtime/frame_log_sink.h"

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& rec, std::vector<std::string> pinned) {
  FrameReport report;
  report.pose = poseFieldsOf(rec);    // frames.jsonl's projections, written by the same tables
  report.knobs = knobFieldsOf(rec);
  report.knobs.pinned = std::move(pinned);
  return report;
}

}  // namespace sb::daemon
