#pragma once
// The per-frame log, frames.jsonl: one JSON object per frame with the knobs it ran with, stage times (ms,
// classic stage names), tracking result, velocity, the controller's triggers and next knobs. Each line is
// written as its frame ends (LineFile: a crash loses at most the frame in hand; a failed write throws).

#include <nlohmann/json.hpp>
#include <string>

#include "runtime/line_file.h"
#include "runtime/output_sink.h"

namespace sb {

// {"csr": 1, "icp": 1e-5, "pd": [10, 5, 4], "tr": 1, "ir": 2}
nlohmann::json knobsToJson(const Knobs& knobs);
// One frames.jsonl object (see the file comment).
nlohmann::json frameRecordToJson(const FrameRecord& record);

class FrameLogSink final : public OutputSink {
 public:
  // Creates (truncates) `path`. Throws sb::Error if it cannot.
  explicit FrameLogSink(const std::string& path);
  void onFrame(const FrameRecord& record) override;
  void flush() override;

 private:
  LineFile out_;
};

}  // namespace sb
