#pragma once
// Replays a sequence in TUM RGB-D layout: `depth.txt` (`timestamp filename` per line, '#' comments),
// 16-bit grayscale depth PNGs, optional `groundtruth.txt` and `calibration.json`. Also reads ICL-NUIM and
// 7-Scenes sequences converted to this layout, and the project's synthetic sequences.
//
// SequenceInfo::format: calibration.json's `format` key when present; otherwise "7scenes" when its
// `invalid_depth_values` include 65535 (7-Scenes marks missing depth so); otherwise "tum".
// Defaults when neither calibration.json nor the options give them: TUM's fx = fy = 525, cx = 319.5,
// cy = 239.5, and depth scale 5000 (1000 for "7scenes"), with a warning.
// Image size: options > calibration.json > the first frame's PNG; every frame must have that size.

#include <optional>
#include <string>
#include <vector>

#include "drivers/frame_source.h"
#include "drivers/random_access_source.h"
#include "drivers/sequence.h"

namespace sb {

class TumReader : public RandomAccessSource {
 public:
  // Reads depth.txt and checks that every selected depth file exists. Throws sb::Error.
  TumReader(const std::string& directory, const SequenceOptions& options);

  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override;
  size_t count() const override { return entries_.size(); }
  DepthFrame load(size_t i) const override { return loadEntry(entries_.at(i)); }

 private:
  struct Entry {
    size_t index = 0;      // position in depth.txt's frame list
    size_t line = 0;       // 1-based line number in depth.txt
    double timestamp = 0;  // seconds
    std::string path;      // depth PNG
  };

  DepthFrame loadEntry(const Entry& entry) const;
  [[noreturn]] void fail(const Entry& entry, const std::string& what) const;

  SequenceInfo info_;
  std::string indexPath_;
  std::vector<Entry> entries_;  // the selected frames only (firstFrame / maxFrames applied)
  std::vector<uint16_t> invalidValues_;
  size_t cursor_ = 0;
};

}  // namespace sb
