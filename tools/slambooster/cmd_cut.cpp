// `slambooster cut SRC --frames LIST --out DIR`: a sequence cut from a TUM-layout directory by a frame list,
// pointing at the source's depth images (nothing copied), with ground truth at the cut's new timestamps
// (drivers/tum_cut.h). "0-299,100-199" makes a real-data kidnap: a jump back to frames seen earlier.

#include <cstdio>
#include <memory>
#include <string>

#include "drivers/tum_cut.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

struct CutArgs {
  std::string source, frames, out;
  CutOptions options;
};

void runCut(const CutArgs& a) {
  const CutResult r = cutTumSequence(a.source, parseFrameList(a.frames), a.out, a.options);
  std::printf("cut: wrote %zu frames of '%s' (frames %s, every %.6f s) to %s; %zu with a reference pose\n",
              r.frames, a.source.c_str(), a.frames.c_str(), r.frameIntervalS, a.out.c_str(),
              r.groundTruthPoses);
  for (const CutJump& j : r.jumps) {
    if (j.translationM < 0)
      std::printf("cut: jump at frame %zu (source %zu -> %zu): no reference pose either side\n", j.frame,
                  j.fromSource, j.toSource);
    else
      std::printf("cut: jump at frame %zu (source %zu -> %zu): %.3f m, %.1f deg\n", j.frame, j.fromSource,
                  j.toSource, j.translationM, j.rotationDeg);
  }
}

}  // namespace

void addCutCommand(CLI::App& app) {
  auto args = std::make_shared<CutArgs>();
  auto* sub = app.add_subcommand(
      "cut",
      "Cut a TUM-layout sequence by a frame list (e.g. a kidnap: 0-299,100-199), without copying images");
  sub->add_option("source", args->source, "Source sequence directory (TUM layout)")->required();
  sub->add_option("--frames", args->frames,
                  "Source frames in the order wanted: comma-separated 0-based inclusive ranges A-B or single "
                  "frames, e.g. 0-299,100-199")
      ->required();
  sub->add_option("--out", args->out, "Output directory (created; must be empty unless --overwrite)")
      ->required();
  sub->add_option("--max-dt", args->options.maxTimeDifferenceS,
                  "A frame's reference pose is the source's nearest in time within this, seconds")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sub->add_flag(
      "--overwrite", args->options.overwrite,
      "Replace the cut's files (depth.txt, groundtruth.txt, calibration.json, segments.csv) in --out");
  sub->callback([args] { runCut(*args); });
}

}  // namespace sb::cli
