#pragma once
// The per-frame log of a run (frames.jsonl, one JSON object per line) as columns for plotting. Reading is
// forgiving: a bad or truncated line is skipped and reported (file and line), missing keys become NaN, so a
// partial log still gives a partial report. The keys read are listed in report/README.md.

#include <array>
#include <string>
#include <vector>

namespace sb::report {

struct FrameLog {
  // One entry per frame read, in file order. NaN where the line lacks the key.
  std::vector<double> frame;           // "frame" (else the running index)
  std::vector<double> timestamp;       // "timestamp", s
  std::vector<double> csr, icp, pd0;   // "knobs": csr, icp, pd[0]
  std::vector<double> computationMs;   // "computation_ms"
  std::vector<double> tracked;         // "tracked": 1 or 0
  std::vector<double> trackingAttempted;  // "tracking_attempted": 1 or 0
  std::vector<double> velocity;        // "velocity_m_per_frame"
  std::vector<double> joules;          // "joules" (null = unknown)
  std::vector<double> powerW;          // "power_w"
  std::vector<std::string> stageNames;         // keys of "ms", in first-seen order
  std::vector<std::vector<double>> stageMs;    // [stage][frame]
  std::vector<double> level;           // "level": the controller's approximation level, when it has one
  std::vector<double> conditioning;    // "conditioning": tracking quality of the ICP problem (NaN: ICP did not run)
  std::vector<double> constrained;     // "constrained": 1 or 0 (NaN: ICP did not run)
  // "state": the tracking state, as the index of core/tracking_state.h (0 good, 1 weak, 2 lost,
  // 3 relocalised, 4 odometry); NaN where the line has none (runs before the state existed).
  std::vector<double> state;
  // Frames where each controller trigger fired ("triggers": ["surface", ...]), in first-seen order; a frame
  // with "corrected": true counts as a "correction" trigger.
  struct Trigger {
    std::string name;
    std::vector<double> frames;
  };
  std::vector<Trigger> triggers;
  bool recordsTriggers = false;  // some line has "triggers" or "corrected" (else: no controller information)

  // The final pose of each frame ("position" x y z, "quaternion" qx qy qz qw: T_camera_to_world in the volume
  // frame, as trajectory.tum but for every frame, lost ones included); NaN where the line has none.
  std::vector<std::array<double, 7>> pose;
  // The fusion's verdict on the wheels per frame: every field of the line's "odometry" object, read without
  // knowing its names, so that a verdict the runtime adds shows up in the report as it is. Booleans and numbers
  // are columns (true = 1, NaN where the line lacks the field); strings are kept per frame ("" where absent).
  struct OdometryColumn {
    std::string name;
    bool boolean = true;          // every value seen was a boolean
    std::vector<double> values;
  };
  struct OdometryText {
    std::string name;
    std::vector<std::string> values;
  };
  std::vector<OdometryColumn> odometry;        // in first-seen order
  std::vector<OdometryText> odometryText;      // in first-seen order
  bool recordsOdometry = false;                // some line has an "odometry" object
  const OdometryColumn* odometryColumn(const std::string& name) const;  // nullptr when never seen

  // Frames of the named trigger (empty when it never fired).
  const std::vector<double>& triggerFrames(const std::string& name) const;

  size_t size() const { return frame.size(); }
  bool hasColumn(const std::vector<double>& column) const;  // any finite value
};

struct FrameLogReadResult {
  FrameLog log;
  std::vector<std::string> problems;  // "frames.jsonl line 7: ..." (capped, with a count of the rest)
};

// Frames a report reads at most (the newest): 100,000 frames (about 55 minutes at 30 fps) keep the report's
// memory and size bounded (a 10^6-frame replay read whole took 1.9 GiB and wrote a 440 MB report).
constexpr size_t kMaxReportFrames = 100000;

// Reads `path`, keeping the newest `maxFrames` frames (0: all). A missing or unreadable file is a problem, not
// an exception.
FrameLogReadResult readFrameLog(const std::string& path, size_t maxFrames = kMaxReportFrames);

}  // namespace sb::report
