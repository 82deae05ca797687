#pragma once
// The per-frame log, frames.jsonl: one JSON object per frame with the knobs it ran with, stage times (ms,
// classic stage names), tracking result, final pose, velocity, the controller's triggers and next knobs.
// frameRecordToJson is the one encoder of a frame: its pose fields are written by the pose record's table
// (core/pose_fields.h), from poseFieldsOf, as the daemon's POSE is (daemon/frame_report.h); its knob fields by
// the knob record's table (pipeline/knob_fields.h), from knobFieldsOf, as KNOBS is; its tracking and
// controller fields by core/frame_log_fields.h's table, from frameLogFieldsOf. Each line is written as
// its frame ends (RotatingFile: a crash loses at most the frame in hand; a failed write throws). With a
// segment store the log is rotated (frames-000001.jsonl, ...; core/rotating_file.h).

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/rotating_file.h"
#include "report/run_summary.h"
#include "runtime/output_sink.h"

namespace sb {

struct PoseFields;  // core/pose_fields.h
struct KnobFields;  // pipeline/knob_fields.h
struct FrameLogFields;  // core/frame_log_fields.h

// The frame's pose record (core/pose_fields.h): the one projection of a record that frames.jsonl and POSE write.
PoseFields poseFieldsOf(const FrameRecord& record);
// The frame's knob record (pipeline/knob_fields.h), the one projection that frames.jsonl and KNOBS write; its
// pins are the daemon's (left empty here: frames.jsonl does not write them).
KnobFields knobFieldsOf(const FrameRecord& record);
// The frame's tracking and controller record (core/frame_log_fields.h): frames.jsonl's alone.
FrameLogFields frameLogFieldsOf(const FrameRecord& record);

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
