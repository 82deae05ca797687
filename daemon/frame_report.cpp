#include "daemon/frame_report.h"

#include "runtime/frame_log_sink.h"

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& rec, std::vector<std::string> pinned) {
  const FrameResult& r = rec.result;
  FrameReport report;
  report.pose = poseFieldsOf(rec);  // frames.jsonl's projection, written by the same table
  KnobFields& k = report.knobs;
  k.frame = r.frame;
  k.controller = rec.controller;
  k.computationMs = r.times.computationMs();
  k.knobs = r.knobs;
  report.pinned = std::move(pinned);
  return report;
}

}  // namespace sb::daemon
