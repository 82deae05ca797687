#pragma once
// summary.json of a run, as one type (issue 32): written whole by runtime/run.h (through
// runtime/summary_sink.h) for `slambooster run` and for every daemon pass alike, and read back by every
// consumer (bench, dse, profile, compare, the report, the scripts through its keys). The JSON keys are the
// file's; `schema_version` says which shape a file has (0: a file from before the type, read as far as its
// keys go; a newer version than this code knows is refused).
//
//   RunSummary s = readRunSummary(dir + "/summary.json");   // throws sb::Error naming the file and key
//   s.frames; s.ate->rmseM; s.joulesPerFrame();
//
// Three sub-objects stay the JSON objects their owners write, shown whole by the report: the pipeline config
// (pipeline/config.h configToJson, whose schema is the pipeline's; code reads one key of it, typed by
// constrainedMinConditioning), the controller sections (controller/registry.h: each controller's settings, read
// by no code) and the navigation map (navmap/nav_map_sink.h). The energy totals and the moving volume are typed
// below, written and read here; the initial knobs are pipeline/knobs.h's, by its key table.

#include <cstddef>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipeline/knobs.h"

namespace sb {

// The shape this code writes. 1: the first typed summary (front_end, schema_version; the daemon writes
// controller, knobs, threads and machine as `run` does).
inline constexpr int kRunSummarySchema = 1;

// Where a run was timed ("machine"): runs timed on different machines are not comparable.
struct MachineInfo {
  std::string host, cpuModel;   // host name; "model name" of /proc/cpuinfo
  unsigned coresOnline = 0;     // cores online
  unsigned threadsUsed = 0;     // the run's worker threads
  std::string backend, device;  // compute backend ("cpu", "opencl") and its device
};

// The daemon's pass ("daemon"): absent for `slambooster run`.
struct DaemonPass {
  uint32_t pass = 0;     // 1-based pass of the input
  std::string cpus;      // CPUs the SLAM thread is pinned to ("4-7")
  unsigned threads = 0;  // compute threads
};

// Absolute trajectory error against the sequence's ground truth ("ate"), metres.
struct AteSummary {
  double rmseM = 0, meanM = 0, maxM = 0, medianM = 0, unalignedMeanM = 0;
  size_t matches = 0;  // associated poses
};

// Tracking states over the run ("tracking_state"; core/tracking_state.h).
struct TrackingStateSummary {
  std::map<std::string, size_t> frames;  // state name -> frames
  size_t lostStretches = 0, longestLostFrames = 0, recoveries = 0, longestFramesToRecover = 0;
  double meanFramesToRecover = 0.0;
  bool lostAtEnd = false;
};

// The robot's odometry the run was given ("odometry"; odometry/odometry_input.h): absent without one.
struct OdometrySummary {
  std::string source;         // where from: a file's path, "BAG TOPIC ...", "socket", ...
  size_t samples = 0;         // samples the track held at the last frame
  size_t framesWithPose = 0;  // frames whose stamp the odometry covered (interpolated)
  double pathM = 0.0;         // the odometry camera's path over those frames, metres
  // The wheels' errors as the run learnt them at its last frame (odometry/odometry_calibration.h).
  double scaleError = 0.0;        // the distance read (1 + this) times the truth
  double yawScaleError = 0.0;     // turns read (1 + this) times the truth ...
  double yawBiasDegPerS = 0.0;    // ... plus this drift
  size_t calibrationFrames = 0;   // frames that brought evidence
  // The camera mount's tilt error learnt (odometry/mount_calibration.h): degrees; where from ("floor": the floor's
  // normal, "turns": the view's turns, "": not learnt); the turning seen (degrees) and the frames whose floor was
  // read.
  double mountErrorDeg = 0.0;
  std::string mountLearntFrom{};
  double mountTurnSeenDeg = 0.0;
  size_t mountFloorFrames = 0;
  // The odometry's clock against the frames' (odometry/time_offset.h): seconds added to a frame's stamp, and
  // whether the turns' evidence moved it from odometry.time_offset_s.
  double timeOffsetS = 0.0;
  bool timeOffsetLearnt = false;
  // The run started from the calibration an earlier run kept in its map store (runtime/kept_odometry.h): the
  // file, and the values it started with (absent: the prior, all zero).
  std::optional<std::string> calibrationFrom{};
  std::optional<double> startScaleError{}, startYawScaleError{}, startYawBiasDegPerS{}, startMountErrorDeg{};
  std::optional<double> startTimeOffsetS{};  // the clock offset kept, when this run's config took it (seconds)
  // The mount the odometry assumes against the one the kept mount correction was learnt against (degrees between
  // their up axes), and why the kept correction was not restored (the mount differs, or is not recorded).
  std::optional<double> startMountChangeDeg{};
  std::optional<std::string> startMountRefused{};
  std::optional<size_t> startCalibrationFrames{};
};

struct StoppedSummary {  // `run --stop-after-ms` stopped the run ("stopped")
  size_t atFrame = 0;
  double limitMs = 0.0, computationMs = 0.0;
};

struct InterruptedSummary {  // a signal ended the run ("interrupted")
  std::string signal;
  size_t atFrame = 0;
};

// The energy totals over the frames so far ("energy"; runtime/energy_account.h fills it from
// power/energy_ledger.h EnergyTotals): absent without a meter. Unknown values are NaN (null in the file).
struct EnergySummary {
  std::string meter, device;                          // the meter's name and device
  size_t frames = 0, knownFrames = 0, unknownFrames = 0;  // frames resolved; of them with joules known, unknown
  double joules = 0, joulesAboveIdle = 0;             // J over the known frames (above the idle baseline)
  double seconds = 0, idleWatts = 0;                  // s of the known frames; the idle baseline (W)
  double joulesPerFrame = NAN, meanWatts = NAN;       // J per known frame; W over them
  double spanSeconds = 0, spanKnownSeconds = 0, spanJoules = 0, spanMeanWatts = NAN;  // the run as a whole
  std::map<std::string, size_t> unknownReasons;       // why a frame's joules are unknown -> frames
};

// The moving volume ("moving_volume"; runtime/map_slabs.h movingVolumeSummary): absent with a fixed volume.
struct MovingVolumeSummary {
  size_t shifts = 0;              // per axis
  double shiftMs = 0, slabMs = 0;  // the backend's moves; reading slabs out, summed
  std::array<double, 3> cornerM{};  // the volume's corner in the world frame, metres
  // The slabs' worker (map_slabs/), present only when the run meshed slabs.
  std::optional<double> slabWorkerMs, slabWaitMs, slabQueuePeakMib;
  std::optional<size_t> slabFilesRemoved;
};

struct RunSummary {
  int schemaVersion = kRunSummarySchema;
  // What ran: set at the start by the run setup (runtime/run_setup.h), the same for both front ends.
  std::string frontEnd;    // "run" (slambooster run) or "daemon" (a pass of slamboosterd)
  std::string sequence;    // the input's path
  std::string controller;  // the controller the run started with (a daemon may switch: controllerFrames)
  nlohmann::json controllerSections = nlohmann::json::object();  // its settings sections (owner's JSON)
  std::optional<Knobs> knobs;  // the controller's initial knobs ("knobs", as frames.jsonl writes a frame's)
  nlohmann::json config = nlohmann::json::object();              // the pipeline config (owner's JSON)
  unsigned threads = 0;                                          // worker threads
  std::optional<MachineInfo> machine;
  std::optional<DaemonPass> daemon;

  // Counts over the frames so far (runtime/summary_sink.h RunStats).
  size_t frames = 0, trackingAttempted = 0, tracked = 0, integrated = 0, corrected = 0;
  size_t halfWishFrames = 0, unconstrained = 0, retracked = 0, halfAppliedFrames = 0;
  double trackedPercent = 0.0;                    // of the frames where tracking was attempted
  double computationMsPerFrame = 0.0;             // preprocessing + tracking + integration + raycast, mean
  double controllerMsPerFrame = 0.0;              // Controller::decide, mean
  std::map<std::string, double> stageMsPerFrame;  // classic stage name -> mean ms
  // What integrate and raycast did (pipeline/stages.h StageWork): integrate_blocks_per_integration (blocks of
  // 8^3 voxels visited), carving_integrations, raycast_samples_per_pixel and raycast_lookups_per_pixel (the
  // march's steps per raycast pixel: tsdf samples, skipping-grid lookups; 0 on the opencl backend, which does
  // not count them).
  std::map<std::string, double> work;
  std::map<std::string, size_t> triggers, knobFrames;  // trigger -> frames; formatKnobs -> frames
  std::map<std::string, size_t> controllerFrames;      // controller -> frames it decided
  TrackingStateSummary trackingState;
  std::optional<OdometrySummary> odometry;

  // At flushes and at the end.
  std::optional<AteSummary> ate;
  std::string ateError;                 // why the ATE is missing although ground truth was given
  std::optional<double> cpuMsPerFrame;  // process CPU time per frame (slambooster run)
  std::optional<StoppedSummary> stopped;
  std::optional<InterruptedSummary> interrupted;
  std::optional<EnergySummary> energy;  // energy totals; absent without a meter
  std::string modelView;                // model.png's viewpoint ("last", "overview"); "" = none written
  std::optional<MovingVolumeSummary> movingVolume;  // absent with a fixed volume
  nlohmann::json navmap;        // the navigation map (navmap/nav_map_sink.h summaryJson); null without one
  nlohmann::json mapStore;      // the kept map (runtime/map_store.h summaryJson); null without one
  std::optional<size_t> meshTriangles, meshSlabs;  // mesh.ply (and the slabs it merged)
  std::optional<bool> complete;                    // every output on disk; absent while the run goes on
  std::string error;                               // why the run ended early or an output failed
  // The output whose write failed first ("error_file": relative to the run's directory when inside it, e.g.
  // "frames.jsonl", "map_slabs/slab-000003.ply"); "" when the run did not end on a write.
  std::string errorFile;

  double joulesPerFrame() const { return energy ? energy->joulesPerFrame : NAN; }  // NaN without a meter
  double meanWatts() const { return energy ? energy->meanWatts : NAN; }
  // config.constrained_min_conditioning (its type checked by fromJson); NaN when absent.
  double constrainedMinConditioning() const;

  nlohmann::json toJson() const;
  // Reads the keys present (absent ones keep their defaults) and checks their types. Throws sb::Error
  // "<where>: key "ate.rmse_m" is "x"; expected a number" or naming a newer schema_version.
  static RunSummary fromJson(const nlohmann::json& j, const std::string& where);
};

// Reads DIR/summary.json-style files: readJsonConfig (bounded nesting, line and column) + fromJson.
RunSummary readRunSummary(const std::string& path);
// The summary of the run in directory `run` (`run`/summary.json; a path ending in ".json" is the file itself).
// A file that is missing or not a regular file throws sb::Error "run summary 'PATH' does not exist: HINT".
RunSummary readRunDirSummary(const std::string& run, const std::string& hint = "");
// Whether the summary file says "complete": true, read alone: a finished run with a damaged field is then
// reported by whoever reads the field (bench leaves it out, naming file, key and value), not run again.
// False when the file is missing or not JSON.
bool runSummaryComplete(const std::string& path);

}  // namespace sb
