// `slambooster synth`: render a synthetic depth sequence of a procedural room along a TUM trajectory (or the
// built-in one, or a stress trajectory) and write it in TUM layout. Stress sequences also get segments.csv
// (label, first frame, end frame) naming their calm / burst / blank-wall parts. `--scene corridor` is a long
// corridor (synth/corridor_scene.h) instead of a room; `--stress drive` drives it, with a volume hint that
// holds the whole path, and odometry.txt beside depth.txt (the base's wheel odometry with stated, seeded errors:
// synth/drive_odometry.h); kidnap's covered frames are written with no depth.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

#include "core/error.h"
#include "core/image.h"
#include "core/thread_pool.h"
#include "core/trajectory.h"
#include "drivers/tum_layout.h"
#include "synth/builtin_trajectory.h"
#include "synth/corridor_scene.h"
#include "synth/drive_odometry.h"
#include "synth/scene_generator.h"
#include "synth/stress_drive.h"
#include "synth/stress_trajectory.h"
#include "synth/synth_sequence.h"
#include "tools/slambooster/commands.h"

namespace sb::cli {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

constexpr double kMaxDriveVolumeM = 256.0;  // a drive's volume hint may be this large, metres
// Stated ranges of the numeric options (refused with a clear message before anything is rendered). Sizes
// stop at what `run` accepts; frame counts stay within what a run of hours needs (30 fps).
constexpr int kMinImageSide = 16;  // pixels; three pyramid levels at csr 8 need at least this
constexpr size_t kMaxSynthFrames = 1000000;
constexpr double kMaxFocalPx = 100000.0;
constexpr double kMaxDepthM = 100.0;
constexpr unsigned kMaxThreads = 1024;

// Refuses nan and infinities (CLI::Range lets nan through: it fails no comparison).
const CLI::Validator kFinite(
    [](std::string& text) {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      return std::isfinite(v) ? std::string() : "must be a finite number, not " + text;
    },
    "FINITE");

struct SynthArgs {
  synth::SynthOptions options;
  std::string trajectory, stress;
  size_t builtinFrames = 0;
  std::optional<int> width, height;
  std::optional<float> fx, fy, cx, cy;
  bool noNoise = false;
  unsigned threads = 0;
  synth::CorridorParams corridor;  // --scene corridor
  synth::OdometryErrors odometry;  // --stress drive: odometry.txt
  synth::DriveFaults faults;       // --stress drive: the base's faults (synth/drive_faults.h)
  std::vector<double> stall, carried, mountError;  // their options as given
  std::string wrong;                               // --odom-wrong KIND,AT,SECONDS[,VALUE]
  std::vector<double> cover;                       // --cover AT,SECONDS
  bool noOdometry = false;
  // --frames-from / --frames-to: a part of the trajectory (frames [from, to) of it; to 0: its end), e.g. two
  // runs of one drive in one building (a restart). Timestamps stay the whole trajectory's.
  size_t framesFrom = 0, framesTo = 0;
};

// Frames [from, to) of `trajectory` (to 0: its end), with the segments and covered frames moved to the part's
// numbering. Throws sb::Error when the part is empty.
void keepPart(size_t from, size_t to, Trajectory& trajectory, std::vector<synth::StressSegment>& segments,
              std::vector<std::pair<size_t, size_t>>& covered) {
  if (from == 0 && to == 0) return;
  const size_t end = to == 0 ? trajectory.size() : std::min(to, trajectory.size());
  if (from >= end)
    throw Error("synth: --frames-from " + std::to_string(from) + " --frames-to " + std::to_string(to) +
                " leaves no frame of the trajectory's " + std::to_string(trajectory.size()) +
                " (need from < to <= frames; to 0 is the end)");
  trajectory = Trajectory(trajectory.begin() + static_cast<std::ptrdiff_t>(from),
                          trajectory.begin() + static_cast<std::ptrdiff_t>(end));
  const auto moved = [&](size_t i) { return std::clamp(i, from, end) - from; };
  std::vector<synth::StressSegment> kept;
  for (synth::StressSegment s : segments) {
    s.begin = moved(s.begin);
    s.end = moved(s.end);
    if (s.begin < s.end) kept.push_back(s);
  }
  segments = std::move(kept);
  std::vector<std::pair<size_t, size_t>> keptCovered;
  for (const auto& [b, e] : covered)
    if (moved(b) < moved(e)) keptCovered.emplace_back(moved(b), moved(e));
  covered = std::move(keptCovered);
}

// The scenes --scene takes: the generated rooms and the corridor.
std::vector<std::string> sceneChoices() {
  std::vector<std::string> names = synth::sceneNames();
  names.push_back(synth::kCorridorSceneName);
  return names;
}

// The fault options' lists into a.faults (validated; throws sb::Error naming the option).
void applyFaultOptions(SynthArgs& a) {
  synth::DriveFaults& f = a.faults;
  if (!a.stall.empty()) {
    f.stallAtS = a.stall[0];
    f.stallS = a.stall[1];
    if (a.stall.size() > 2) f.stallSpeedMps = a.stall[2];
  }
  if (!a.carried.empty()) {
    f.carriedAtS = a.carried[0];
    f.carriedBackM = a.carried[1];
  }
  for (size_t i = 0; i < a.mountError.size(); ++i) f.mountError[i] = a.mountError[i];
  if (!a.wrong.empty()) synth::parseWrongWheelsOption(a.wrong, f);
  if ((!a.stall.empty() && !(a.stall[0] >= 0.0)) || (!a.carried.empty() && !(a.carried[0] >= 0.0)))
    throw Error("synth: --odom-stall and --odom-carried start at a time of at least 0 s");
  try {
    f.validate();
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " (--odom-stall, --odom-carried, --odom-latency, --odom-mount-error)");
  }
}

void runSynth(SynthArgs& a) {
  if (int(!a.trajectory.empty()) + int(a.builtinFrames > 0) + int(!a.stress.empty()) != 1) {
    throw Error("synth: give exactly one of --trajectory FILE (a TUM trajectory), --builtin-frames N (N > 0) or "
                "--stress NAME (" + joined(synth::stressNames()) + ")");
  }
  synth::SynthOptions& o = a.options;
  Intrinsics& k = o.intrinsics;
  if (a.width) k.width = *a.width;
  if (a.height) k.height = *a.height;
  k.cx = a.cx.value_or(0.5f * (k.width - 1));
  k.cy = a.cy.value_or(0.5f * (k.height - 1));
  if (a.fx) k.fx = *a.fx;
  if (a.fy) k.fy = *a.fy;
  if (k.width <= 0 || k.height <= 0 || k.fx <= 0.f || k.fy <= 0.f) {
    throw Error("synth: --width, --height, --fx and --fy must be positive (got " + std::to_string(k.width) + ", " +
                std::to_string(k.height) + ", " + std::to_string(k.fx) + ", " + std::to_string(k.fy) + ")");
  }
  if (!(o.sensor.minDepthM > 0.0 && o.sensor.minDepthM < o.sensor.maxDepthM)) {
    throw Error("synth: need 0 < --min-depth < --max-depth (got " + std::to_string(o.sensor.minDepthM) + ", " +
                std::to_string(o.sensor.maxDepthM) + " m)");
  }
  if (a.noNoise) o.sensor.noise = false;
  if (a.threads > 0) ThreadPool::setGlobalThreads(a.threads);

  std::vector<synth::StressSegment> segments;
  Trajectory trajectory;
  std::optional<synth::Scene> stressScene;  // the scene a stress sequence renders in
  const bool corridor = o.scene == synth::kCorridorSceneName;
  if (corridor) stressScene = synth::generateCorridor(o.seed, a.corridor);
  if (!a.stress.empty() && corridor != (synth::parseStressKind(a.stress) == synth::StressKind::Drive)) {
    throw Error("synth: --stress drive runs in --scene corridor, and the other stress trajectories in a room (" +
                joined(synth::sceneNames()) + "); got --stress " + a.stress + " with --scene " + o.scene);
  }
  if (!a.trajectory.empty()) {
    trajectory = readTumTrajectory(a.trajectory);
  } else if (a.builtinFrames > 0) {
    trajectory = synth::builtinTrajectory(a.builtinFrames);
  } else {
    const synth::StressKind kind = synth::parseStressKind(a.stress);
    const synth::Scene room = corridor ? *stressScene : synth::generateScene(o.scene, o.seed);
    synth::StressTrajectory stress = synth::stressTrajectory(kind, room, o.seed);
    stressScene = synth::stressScene(kind, room);
    o.coveredFrames = synth::coveredFrames(stress);
    if (kind == synth::StressKind::Drive) {  // the volume hint holds the whole drive
      o.volumeHints.holdPath = true;
      o.volumeHints.maxSizeM = kMaxDriveVolumeM;
    }
    trajectory = std::move(stress.poses);
    segments = std::move(stress.segments);
  }
  keepPart(a.framesFrom, a.framesTo, trajectory, segments, o.coveredFrames);
  const bool driveOdometry = !a.stress.empty() && synth::parseStressKind(a.stress) == synth::StressKind::Drive &&
                             !a.noOdometry;
  if (driveOdometry) a.odometry.validate();  // before anything is rendered
  if (!a.cover.empty()) {  // frames [begin, end) of a covered lens: no depth
    if (!(a.cover[0] >= 0.0 && a.cover[1] > 0.0))
      throw Error("synth: --cover AT,SECONDS needs AT >= 0 and SECONDS > 0");
    const double fps = trajectory.size() > 1 ? 1.0 / (trajectory[1].timestamp - trajectory[0].timestamp) : 30.0;
    o.coveredFrames.emplace_back(static_cast<size_t>(a.cover[0] * fps),
                                 static_cast<size_t>((a.cover[0] + a.cover[1]) * fps));
  }
  applyFaultOptions(a);
  if ((a.faults.changesTruth() || !a.faults.describe().empty()) && !driveOdometry)
    throw Error("synth: --odom-stall, --odom-carried, --odom-latency, --odom-mount-error and --odom-wrong need "
                "--stress drive with its odometry");
  if (a.faults.changesTruth()) {  // the truth stands through a stall, or jumps back at a carry
    const synth::stress::DrivePath path = synth::drivePath(*stressScene, o.seed);
    const synth::DriveClock clock(path, a.faults);
    for (TimedPose& pose : trajectory) pose.T_camera_to_world = path.cameraToWorld(clock.at(pose.timestamp));
  }
  const bool tty = isatty(STDERR_FILENO) != 0;
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  auto report = [&](size_t done, size_t total) {
    if (tty) std::fprintf(stderr, "\rsynth: frame %zu/%zu (%.1f frames/s)", done, total, done / seconds());
  };
  const synth::SynthResult r = stressScene ? synth::synthesizeSequence(*stressScene, trajectory, o, report)
                                           : synth::synthesizeSequence(trajectory, o, report);
  if (tty) std::fprintf(stderr, "\n");
  std::printf("synth: wrote %zu frames of scene '%s' (seed %llu, noise %s) to %s in %.1f s\n", r.frames,
              o.scene.c_str(), static_cast<unsigned long long>(o.seed), o.sensor.noise ? "on" : "off",
              o.outDir.c_str(), seconds());
  if (!segments.empty()) {
    const std::string csvPath = o.outDir + "/" + tum::kSegmentsFile;
    std::ofstream csv(csvPath);
    csv << "label,begin_frame,end_frame\n";
    for (const auto& seg : segments)
      if (seg.begin < r.frames) csv << seg.label << "," << seg.begin << "," << std::min(seg.end, r.frames) << "\n";
    if (!csv) throw Error("synth: cannot write '" + csvPath + "'");
    std::printf("synth: stress '%s': %zu segments in %s\n", a.stress.c_str(), segments.size(), csvPath.c_str());
  }
  if (driveOdometry) {
    const synth::stress::DrivePath path = synth::drivePath(*stressScene, o.seed);
    // A part that starts later (--frames-from) has fresh odometry: its frame is the base where the part
    // starts, its noise drawn anew, as a robot restarted there reports it.
    const Trajectory odometry = synth::driveOdometry(path, trajectory[r.frames - 1].timestamp, a.odometry, o.seed,
                                                     trajectory.front().timestamp, a.faults);
    synth::writeOdometryFile(o.outDir + "/odometry.txt", odometry, a.odometry, o.seed, a.faults);
    const std::string faults = a.faults.describe();
    std::printf("synth: odometry: %zu samples in %s/odometry.txt (%s%s%s)\n", odometry.size(), o.outDir.c_str(),
                a.odometry.describe().c_str(), faults.empty() ? "" : "; faults: ", faults.c_str());
  }
  std::printf("synth: valid pixels %.1f%%; volume hint: cube %.2f m, first camera at (%.3f, %.3f, %.3f) of it\n",
              100.0 * r.validFraction, r.volume.sizeM, r.volume.initialPosition[0], r.volume.initialPosition[1],
              r.volume.initialPosition[2]);
}

}  // namespace

void addSynthCommand(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  auto* sub = app.add_subcommand("synth", "Render a synthetic depth sequence of a procedural room (TUM layout)");
  synth::SynthOptions& o = args->options;
  sub->add_option("--out", o.outDir, "Output directory (created; must be empty unless --overwrite)")->required();
  auto* traj = sub->add_option("--trajectory", args->trajectory,
                               "TUM trajectory (camera-to-world), e.g. an ICL-NUIM living-room trajectory");
  auto* builtin = sub->add_option("--builtin-frames", args->builtinFrames,
                                  "Use the built-in handheld-like orbit with this many frames (30 fps)")
                     ->check(CLI::Range(size_t{1}, kMaxSynthFrames));
  auto* stress = sub->add_option("--stress", args->stress,
                                 "Render a stress trajectory for the controller experiments (seeded by --seed; "
                                 "segments.csv names its parts): bursts (calm handheld motion with four 0.5 s "
                                 "bursts of up to 1.15 m/s or 55 deg/s), hard-bursts (the same with bursts of up to "
                                 "1.9 m/s or 126 deg/s), blank-wall (6 s facing a blank wall stretch at a corner), "
                                 "robot (a wheeled robot's camera 1 m up driving a loop at 1.05-1.4 m/s), pan (yaw "
                                 "sweeps of up to 90 deg/s in place) or corridor (sliding along a blank wall with "
                                 "only the wall in view, three times ~75 frames; renders in the room with a 2.4 m "
                                 "stretch of wall cleared), kidnap (9 s of calm mapping, the lens covered, no depth, "
                                 "for 1-3 s while the camera moves, then shown a mapped view), kidnap-unseen (the "
                                 "same, then shown a view no mapping frame saw), or drive (--scene corridor: a "
                                 "wheeled robot's camera 1.2 m up drives the corridor at 1.05-1.45 m/s, U-turns and "
                                 "drives back)")
                     ->check(CLI::IsMember(synth::stressNames()));
  traj->excludes(builtin);
  traj->excludes(stress);
  builtin->excludes(stress);
  sub->add_option("--scene", o.scene, "Procedural room, or corridor (a long corridor; see --corridor-length)")
      ->check(CLI::IsMember(sceneChoices()))
      ->capture_default_str();
  sub->add_option("--corridor-length", args->corridor.lengthM,
                  "Length of --scene corridor, metres (a drive covers it less 1.5 m at each end, twice)")
      ->check(CLI::Range(4.0, 200.0))
      ->capture_default_str();
  sub->add_option("--corridor-spacing", args->corridor.spacingScale,
                  "Scale of the gaps between --scene corridor's wall features and lights (1: 0.3-1.5 m; 4 and more "
                  "leave stretches where nothing across the corridor fixes motion along it)")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  sub->add_option("--seed", o.seed, "Seed of the furniture layout and the sensor noise")->capture_default_str();
  sub->add_option("--frames", o.maxFrames, "Render at most this many frames (0 = all)")
      ->check(CLI::Range(size_t{0}, kMaxSynthFrames))
      ->capture_default_str();
  sub->add_option("--frames-from", args->framesFrom,
                  "Render the trajectory from this frame on (0-based; timestamps stay the trajectory's). With "
                  "--frames-to, two parts of one drive are two runs in one building (a restart); a drive's part "
                  "gets fresh odometry, its frame the base where the part starts")
      ->check(CLI::Range(size_t{0}, kMaxSynthFrames))
      ->capture_default_str();
  sub->add_option("--frames-to", args->framesTo,
                  "Render the trajectory up to this frame, exclusive (0 = its end); before --frames")
      ->check(CLI::Range(size_t{0}, kMaxSynthFrames))
      ->capture_default_str();
  sub->add_flag("--no-noise", args->noNoise,
                "Exact depth: no disparity noise, quantisation, or grazing/edge dropouts (range limits stay)");
  sub->add_option("--noise-sigma", o.sensor.sigmaDisparityPx, "Disparity noise std, pixels")
      ->check(kFinite & CLI::Range(0.0, 10.0))
      ->capture_default_str();
  sub->add_option("--min-depth", o.sensor.minDepthM, "Nearest valid depth, metres")
      ->check(kFinite & CLI::Range(0.0, kMaxDepthM))
      ->capture_default_str();
  sub->add_option("--max-depth", o.sensor.maxDepthM, "Farthest valid depth, metres")
      ->check(kFinite & CLI::Range(0.0, kMaxDepthM))
      ->capture_default_str();
  sub->add_option("--width", args->width, "Image width, pixels (default 640)")
      ->check(CLI::Range(kMinImageSide, kMaxDepthImageSide));
  sub->add_option("--height", args->height, "Image height, pixels (default 480)")
      ->check(CLI::Range(kMinImageSide, kMaxDepthImageSide));
  sub->add_option("--fx", args->fx, "Focal length x, pixels (default 481.2)")
      ->check(kFinite & CLI::Range(0.0, kMaxFocalPx));
  sub->add_option("--fy", args->fy, "Focal length y, pixels (default 480)")
      ->check(kFinite & CLI::Range(0.0, kMaxFocalPx));
  sub->add_option("--cx", args->cx, "Principal point x, pixels (default (width-1)/2)")
      ->check(kFinite & CLI::Range(0, kMaxDepthImageSide));
  sub->add_option("--cy", args->cy, "Principal point y, pixels (default (height-1)/2)")
      ->check(kFinite & CLI::Range(0, kMaxDepthImageSide));
  sub->add_option("--threads", args->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(0u, kMaxThreads));
  synth::OdometryErrors& odo = args->odometry;
  const char* const odometryGroup = "Odometry of --stress drive (odometry.txt)";
  sub->add_flag("--no-odometry", args->noOdometry, "--stress drive: do not write odometry.txt")
      ->group(odometryGroup);
  sub->add_option("--odom-rate", odo.rateHz, "Odometry samples per second (Hz)")
      ->check(kFinite & CLI::Range(1.0, 1000.0))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-scale", odo.scale,
                  "Scale error of the distance driven (0.03: it reads 3% long; applied per increment)")
      ->check(kFinite & CLI::Range(-0.5, 0.5))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-yaw-scale", odo.yawScale, "Scale error of the turns (0.02: they read 2% large)")
      ->check(kFinite & CLI::Range(-0.5, 0.5))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-yaw-bias", odo.yawBiasDegps, "Yaw drift, degrees per second (also at rest)")
      ->check(kFinite & CLI::Range(-30.0, 30.0))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-noise", odo.noiseMPerSqrtM,
                  "Translation noise: std of its random walk after 1 m driven, metres")
      ->check(kFinite & CLI::Range(0.0, 1.0))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-yaw-noise", odo.yawNoiseDegPerSqrtS,
                  "Yaw noise: std of its random walk after 1 s, degrees")
      ->check(kFinite & CLI::Range(0.0, 10.0))
      ->capture_default_str()
      ->group(odometryGroup);
  sub->add_option("--odom-slip-at", odo.slipAtS,
                  "A wheel slip at this time, seconds: one step reads --odom-slip-m more forward motion")
      ->check(kFinite & CLI::Range(0.0, 1e6))
      ->group(odometryGroup);
  sub->add_option("--odom-slip-m", odo.slipM, "The wheel slip's extra forward reading, metres")
      ->check(kFinite & CLI::Range(-10.0, 10.0))
      ->capture_default_str()
      ->group(odometryGroup);
  const char* const faultGroup = "Faults of --stress drive's base (the truth and odometry.txt)";
  sub->add_option("--cover", args->cover, "AT,SECONDS: the lens is covered (no depth) from AT s for SECONDS")
      ->expected(2)
      ->delimiter(',')
      ->group(faultGroup);
  sub->add_option("--odom-stall", args->stall,
                  "AT,SECONDS[,SPEED]: the robot stands from AT s for SECONDS while its wheels read SPEED m/s "
                  "(default 1)")
      ->expected(2, 3)
      ->delimiter(',')
      ->group(faultGroup);
  sub->add_option("--odom-carried", args->carried,
                  "AT,METRES: the robot is lifted at AT s and set down METRES back along its path; the wheels "
                  "never turn")
      ->expected(2)
      ->delimiter(',')
      ->group(faultGroup);
  sub->add_option("--odom-latency", args->faults.latencyS,
                  "The odometry's stamps are this many seconds later than its poses' true time")
      ->check(kFinite & CLI::Range(-1.0, 1.0))
      ->group(faultGroup);
  sub->add_option("--odom-mount-error", args->mountError,
                  "ROLL,PITCH,YAW[,X,Y,Z]: the camera mount the odometry assumes is the true one turned by these "
                  "degrees (about the optical z, x, y axes) and moved by these metres (camera frame)")
      ->expected(3, 6)
      ->delimiter(',')
      ->group(faultGroup);
  sub->add_option("--odom-wrong", args->wrong,
                  "KIND,AT,SECONDS[,VALUE]: the odometry alone is wrong for SECONDS from AT s (the truth drives on): "
                  "reversed (each step read backwards), zero (no motion read), gyro (a further turn drift of VALUE "
                  "deg/s, default 20), scaled (each step times VALUE, default 2)")
      ->group(faultGroup);
  sub->add_flag("--overwrite", o.overwrite, "Replace the contents of a non-empty --out directory");
  sub->callback([args] { runSynth(*args); });
}

}  // namespace sb::cli
