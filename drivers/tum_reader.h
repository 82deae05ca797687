#pragma once
// Replays a sequence in TUM RGB-D layout: a frame index (drivers/tum_index.h: `depth.txt`, else
// `associations.txt`), 16-bit grayscale depth PNGs, optional ground truth and `calibration.json`. Reads TUM,
// ICL-NUIM (TUM-compatible archives) and 7-Scenes sequences in this layout, and the project's synthetic ones.
//
// Ground truth: `groundtruth.txt`, else the directory's only `*.freiburg` file (ICL-NUIM's naming).
// SequenceInfo::format: calibration.json's `format` key when present; otherwise "7scenes" when its
// `invalid_depth_values` include 65535 (7-Scenes marks missing depth so); otherwise "icl-nuim" when the
// ground truth is a `*.freiburg` file; otherwise "tum". Defaults for values neither calibration.json nor the
// options give (with a warning): "tum": fx = fy = 525, cx = 319.5, cy = 239.5, 5000 units/m; "icl-nuim": fx =
// 481.2, fy = 480, cx = 319.5, cy = 239.5, 5000 units/m; "7scenes": fx = fy = 585, cx = 320, cy = 240, 1000
// units/m. Image size: options > calibration.json > the first frame's PNG; every frame must have that size
// (checked from the PNG header before decoding). Missing depth files of the selected frames are reported at
// open; unreadable ones at their frame.

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
