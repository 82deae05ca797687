// A run's map store (runtime/map_store.h; issue 55): opening it, localising in a kept one, the store's part of
// each frame, and the state the store keeps beside the TSDF and the keyframes: the navigation map's frame and
// votes (navmap.bin, through the map sink) and the wheels' learnt calibration and clock (odometry.bin). Run's own members
// (runtime/run.h); run.cpp holds the rest of the run.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include "runtime/kept_odometry.h"
#include "runtime/run.h"

namespace sb {

namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
// The mount the odometry assumes is the kept correction's when their up axes (in the camera frame) are at most
// this far apart: a planar odometry's up is the configured mount's exactly, whatever the base does; a 3D one's
// tilts with the floor under the base by a few tenths of a degree. A mount re-measured or re-configured by more
// makes the kept correction wrong by as much, and the floor relearns it in a second of frames.
constexpr double kKeptMountSameDeg = 0.5;
}  // namespace

// Where a restarted robot, or one set down in the run, is tried besides each keyframe: along its view, metres
// (nearest first).
constexpr std::array<double, 4> kKeptMapViewOffsetsM = {0.25, -0.25, 0.5, -0.5};
// A run writing a store, or keeping its slabs in memory, keeps a keyframe at least every this many metres (or 30
// degrees) of its path: a robot set down anywhere on it stands within the view offsets above of one.
constexpr double kKeptMapKeyframeSpacingM = 0.5;

void Run::startMapStore(const RunOutputs& outputs) {
  const PipelineConfig& config = pipeline_->config();
  if (!outputs.mapStore.empty()) {
    mapStore_ = std::make_unique<MapStore>(outputs.mapStore, config, outputs.mapStoreOptions);
  } else if (pipeline_->volumeWindow() && config.relocalise && config.relocaliseKeptMapMib > 0) {
    // An ordinary run keeps the slabs that leave its volume in memory, for its own relocalisation (no file).
    mapStore_ = MapStore::inMemory(config, uint64_t(config.relocaliseKeptMapMib) << 20);
  } else {
    return;
  }
  runner_.monitor().setKeyframeSpacing(kKeptMapKeyframeSpacingM);
  VolumeWindow& window = *pipeline_->volumeWindow();  // MapStore refuses a fixed volume
  if (mapStore_->kept()) {
    // Localising first: nothing fused, the volume placed and filled from the store for each candidate and held
    // there (the held pose is in no frame of the store) until one is confirmed.
    pipeline_->skipBootstrap();
    window.setHeld(true);
    runner_.monitor().startInKeptMap(
        mapStore_->keptKeyframes(),
        [this, &window](const Eigen::Isometry3d& pose) {
          return mapStore_->placeFor(pose, window, pipeline_->backend());
        },
        {kKeptMapViewOffsetsM.begin(), kKeptMapViewOffsetsM.end()});
  }
  restoreStoreState();
  window.setEnterListener([this, &window](const std::array<int, 3>& first, const std::array<int, 3>& extent) {
    mapStore_->swapIn(first, extent, window, pipeline_->backend());
  });
  // Lost in the run (a kidnap, a long failure): candidates anywhere on the kept map, the volume placed for each
  // (stepMapStore keeps the volume and holds the window first).
  runner_.monitor().setRecoveryPrepare(
      [this, &window](const Eigen::Isometry3d& pose) {
        return !recoveringOverStore_ || mapStore_->placeFor(pose, window, pipeline_->backend());
      },
      {kKeptMapViewOffsetsM.begin(), kKeptMapViewOffsetsM.end()});
  outputs_.summary->header().mapStore = mapStore_->summaryJson();
}

void Run::stepMapStore(const FrameRecord& rec) {
  mapStore_->nextFrame();
  if (const std::optional<Eigen::Isometry3d>& c = rec.odometry.cameraToOdom) {
    const Eigen::Vector3d up = c->linear().transpose() * Eigen::Vector3d::UnitZ();
    mountUpSum_ += up;
    if (keptMount_) decideKeptMount(up);
  }
  if (!mapStore_->writing() && !runner_.monitor().localisingInKeptMap()) {
    mapStore_->localised(rec.result.frame, rec.result.timestamp);
    pipeline_->volumeWindow()->setHeld(false);
  }
  // Lost in the run: before the first placement the volume's map (not yet left as slabs) is kept too (placeFor),
  // and the window is held where the relocaliser places it (follow() would bring it back to the held pose) until a
  // candidate is confirmed; from then on the run maps as always, from the volume placed there.
  const TrackingMonitor& monitor = runner_.monitor();
  const bool recovering = monitor.recovering() && !monitor.localisingInKeptMap() && mapStore_->writing() &&
                          pipeline_->config().relocalise;
  if (recovering && !recoveringOverStore_) {
    mapStore_->recoveryStarted(*pipeline_->volumeWindow());
    pipeline_->volumeWindow()->setHeld(true);
    recoveringOverStore_ = true;
  } else if (!recovering && recoveringOverStore_) {
    pipeline_->volumeWindow()->setHeld(false);
    recoveringOverStore_ = false;
  }
  keyframesDirty_ = keyframesDirty_ || rec.keyframeAdded;
  // keyframes.bin at most once a second of frames (30): a killed run loses at most that many new keyframes.
  constexpr size_t kKeyframeSaveFrames = 30;
  if (keyframesDirty_ && mapStore_->writing() && rec.result.frame >= keyframesSavedAt_ + kKeyframeSaveFrames) {
    mapStore_->saveKeyframes(runner_.monitor().relocaliser().keyframes());
    keyframesSavedAt_ = rec.result.frame;
    keyframesDirty_ = false;
  }
  // The map's votes and the wheels' calibration at most every 10 s of frames (300), the votes only once a slab's
  // are in (never waiting for them): a killed run keeps what left its volume, as its slabs.
  constexpr size_t kStateSaveFrames = 300;
  if (mapStore_->writing() && !mapStore_->inMemory() && rec.result.frame >= stateSavedAt_ + kStateSaveFrames) {
    keepStoreState(/*final=*/false);
    stateSavedAt_ = rec.result.frame;
  }
  outputs_.summary->header().mapStore = mapStore_->summaryJson();
}

void Run::restoreStoreState() {
  if (mapStore_->inMemory()) return;
  // The map frame and the votes only for a kept store, whose frame the run localises in; a store without
  // keyframes is a new one (its frame is this run's), and its navmap.bin is replaced.
  const mapstore::StateFile& navmap = mapstore::kNavmapFile;
  if (const std::vector<uint8_t>* payload = mapStore_->keptState(navmap); payload && mapSink_ && mapStore_->kept())
    mapSink_->restoreState(*payload, mapStore_->statePath(navmap));
  // The wheels' calibration whatever the frame: it is the base's, not the map's.
  const mapstore::StateFile& wheels = mapstore::kOdometryFile;
  if (const std::vector<uint8_t>* payload = mapStore_->keptState(wheels)) {
    const std::string path = mapStore_->statePath(wheels);
    const KeptOdometry kept = decodeKeptOdometry(*payload, path, mapStore_->keptStateVersion(wheels));
    odometry::MotionModel& motion = runner_.motion();
    motion.restoreCalibration(kept.calibration);
    keptMount_ = KeptMount{kept.mount, kept.mountUp, path};  // decideKeptMount, once the odometry's mount is seen
    const bool clockKept = motion.restoreTimeOffset(kept.timeOffset);
    if (kept.timeOffset.learnt && !clockKept)
      spdlog::info("map store: the odometry's clock offset {:.3f} s kept in '{}' is not taken: this run's is fixed "
                   "(odometry.time_offset_range_s 0) or its range does not hold it; it starts at {:.3f} s",
                   kept.timeOffset.offsetS, path, motion.timeOffset().offset());
    else if (clockKept)
      spdlog::info("map store: the odometry's clock offset from '{}': {:.3f} s ({} frames of evidence)", path,
                   motion.timeOffset().offset(), kept.timeOffset.frames);
    const odometry::CalibrationEstimate e = motion.calibration().estimate();
    spdlog::info("map store: the wheels' calibration from '{}': distance x{:.4f}, turns x{:.4f}, drift {:.4f} deg/s "
                 "({} frames of evidence)",
                 path, 1.0 + e.scale, 1.0 + e.yawScale, e.yawBiasRadPerS * kRadToDeg, e.frames);
    if (std::optional<OdometrySummary>& o = outputs_.summary->header().odometry) {
      o->calibrationFrom = path;
      o->startScaleError = e.scale;
      o->startYawScaleError = e.yawScale;
      o->startYawBiasDegPerS = e.yawBiasRadPerS * kRadToDeg;
      o->startCalibrationFrames = size_t(e.frames);
      if (clockKept) o->startTimeOffsetS = motion.timeOffset().offset();
    }
  }
}

void Run::decideKeptMount(const Eigen::Vector3d& up) {
  const KeptMount kept = *std::exchange(keptMount_, std::nullopt);
  odometry::MountCalibration keptCorrection;
  keptCorrection.restore(kept.state);
  std::optional<OdometrySummary>& o = outputs_.summary->header().odometry;
  std::string refused;
  if (kept.up) {
    const double changeDeg = std::acos(std::clamp(kept.up->dot(up.normalized()), -1.0, 1.0)) * kRadToDeg;
    if (o) o->startMountChangeDeg = changeDeg;
    if (changeDeg > kKeptMountSameDeg) {
      char why[160];
      std::snprintf(why, sizeof why, "the odometry's mount differs by %.2f deg (more than %.1f) from the one the kept "
                    "correction was learnt against", changeDeg, kKeptMountSameDeg);
      refused = why;
    }
  } else {
    refused = "the store does not record the mount the kept correction was learnt against (an odometry.bin of "
              "version 1)";
  }
  if (!refused.empty()) {
    spdlog::warn("map store: the mount's correction kept in '{}' ({:.2f} deg) is not restored: {}; it is learnt "
                 "afresh (summary.json odometry.start_mount_refused)", kept.path, keptCorrection.errorDeg(), refused);
    if (o) o->startMountRefused = refused;
    return;
  }
  runner_.motion().restoreMount(kept.state);
  spdlog::info("map store: the mount's correction from '{}': {:.2f} deg, learnt against the same mount", kept.path,
               keptCorrection.errorDeg());
  if (o) o->startMountErrorDeg = keptCorrection.errorDeg();
}

void Run::keepStoreState(bool final) {
  if (!mapStore_->writing() || mapStore_->inMemory()) return;
  if (mapSink_ && (final || mapSink_->keptStateChanged()))
    mapStore_->saveState(mapstore::kNavmapFile, mapSink_->keptState(*pipeline_, final));
  // The calibration only from a run with odometry (a run without keeps what the store held).
  if (runner_.odometry()) {
    const odometry::MotionModel& motion = runner_.motion();
    KeptOdometry kept{motion.calibration().state(), motion.mount().state(), motion.timeOffset().state(), {}};
    if (mountUpSum_.norm() > 0.0) kept.mountUp = mountUpSum_.normalized();
    if (keptMount_) {  // the odometry never gave a pose: the kept mount stays as it was
      kept.mount = keptMount_->state;
      kept.mountUp = keptMount_->up;
    }
    mapStore_->saveState(mapstore::kOdometryFile, encodeKeptOdometry(kept));
  }
}

}  // namespace sb
