#pragma once
// What the socket publishes of a frame's record (runtime/frame_record.h): POSE's fields, the pose record
// frames.jsonl writes too (runtime/frame_log_sink.h's poseFieldsOf, core/pose_fields.h's table), and KNOBS's,
// the knob record frames.jsonl writes too (knobFieldsOf, pipeline/knob_fields.h's table) with the daemon's pins.

#include <string>
#include <vector>

#include "daemon/protocol.h"
#include "runtime/frame_record.h"

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& record, std::vector<std::string> pinned);

}  // namespace sb::daemon
