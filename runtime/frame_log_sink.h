#pragma once
// The per-frame log, frames.jsonl: one JSON object per frame with the knobs it ran with, stage times (ms,
// classic stage names), tracking result, final pose, velocity, the controller's triggers and next knobs.
// frameRecordToJson is the one encoder of a frame: the daemon's POSE and KNOBS messages are typed projections
// of the same record (daemon/frame_report.h), each field under its frames.jsonl name. Each line is
// written as its frame ends (RotatingFile: a crash loses at most the frame in hand; a failed write throws).
// With a segment store the log is rotated (frames-000001.jsonl, ...; core/rotating_file.h).

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/rotating_file.h"
#include "report/run_summary.h"
#include "runtime/output_sink.h"

namespace sb {

// One frames.jsonl object (see the file comment); also what the daemon publishes (daemon/protocol.h).
nlohmann::json frameRecordToJson(const FrameRecord& record);

class FrameLogSink final : public OutputSink {
 public:
  // Creates (truncates) DIR/frames.jsonl, or with `segments` its first new segment. Throws sb::Error if it
  // cannot.
  explicit FrameLogSink(const std::string& dir, std::shared_ptr<SegmentStore> segments = nullptr);
  void onFrame(const FrameRecord& record) override;
  void flush() override;
  RotatingFile& file() { return out_; }

 private:
  RotatingFile out_;
};

}  // namespace sb
