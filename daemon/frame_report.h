#pragma once
// The one projection of a frame's record (runtime/frame_record.h) onto what the socket publishes: POSE's and
// KNOBS's typed fields (daemon/protocol.h). The frame is encoded once, for frames.jsonl
// (runtime/frame_log_sink.h); the socket's messages are written from these fields.

#include <string>
#include <vector>

#include "daemon/protocol.h"
#include "runtime/frame_record.h"

namespace sb::daemon {

FrameReport frameReport(const FrameRecord& record, std::vector<std::string> pinned);

}  // namespace sb::daemon
