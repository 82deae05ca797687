#pragma once
// The pass directories of a looping replay (source.at_end "loop": output.dir/pass-0001, pass-0002, ...). A
// replay that loops for weeks must not fill the disk with them: each directory, once its pass has ended, is
// handed whole to the retention of the outputs (core/segment_store.h: output.rotation's keep_mib,
// keep_segments and min_free_mib), which removes the oldest first. Numbering goes on after the directories
// already there (a restarted daemon never writes into an earlier pass's directory), and those join the
// retention at once.
//
//   PassDirectories passes(config.output.dir, store);
//   const std::string dir = passes.next();   // output.dir/pass-NNNN of the pass that starts
//   ...                                      // the pass ends: its Run (and its rotating files) closed
//   passes.close(dir);

#include <cstdint>
#include <memory>
#include <string>

#include "core/segment_store.h"

namespace sb::daemon {

class PassDirectories {
 public:
  // Registers the pass directories already in `outputDir` with `store` (oldest by modification time).
  PassDirectories(std::string outputDir, std::shared_ptr<SegmentStore> store);

  // The directory of the next pass (not created).
  std::string next();
  // The pass in `dir` ended and every file in it is closed: it joins the retention.
  void close(const std::string& dir);

 private:
  std::string outputDir_;
  std::shared_ptr<SegmentStore> store_;
  uint64_t last_ = 0;  // the highest pass number used or found
};

// "pass-0007" -> 7; 0 when `name` is not a pass directory's name.
uint64_t passNumber(const std::string& name);

}  // namespace sb::daemon
