#pragma once
// What the socket publishes of a frame's record (runtime/frame_record.h): POSE's fields, the pose record
// frames.jsonl writes too (runtime/frame_log_sink.h's poseFieldsOf, core/pose_fields.h's table), and KNOBS's
// (daemon/protocol.h).

#include <string>
#include <vector>

#include "daemon/protocol.h"
#include "runtime/frame_record.h"

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& record, std::vector<std::string> pinned);

}  // namespace sb::daemon
