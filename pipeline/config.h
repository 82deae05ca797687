#pragma once
// Every constant of the KinectFusion pipeline (architecture.md D2) as a named field with its unit and the
// reference (SLAMBench KinectFusion) default. Fixed for a run; the per-frame knobs are in knobs.h.

#include <array>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "pipeline/knobs.h"

namespace sb {

// Which compute backend runs the stages (architecture.md D3). `automatic`: OpenCL on a GPU or accelerator
// device when one is found (or the device opencl_platform / opencl_device name), else the cpu backend.
enum class BackendKind { automatic, cpu, opencl };
const char* backendKindName(BackendKind kind);  // "auto", "cpu", "opencl"

// Whether the volume follows the camera (pipeline/volume_window.h, docs/moving-volume.md). `automatic`: the
// command decides: `slambooster run` and the daemon move it (the product), the library and the experiment
// matrix (bench, dse, profile run `slambooster run --fixed-volume`: the paper's reproduction) keep it fixed.
enum class VolumeMode { automatic, moving, fixed };
const char* volumeModeName(VolumeMode mode);  // "auto", "moving", "fixed"

struct PipelineConfig {
  // --- preprocessing ---
  int bilateralRadius = 2;              // pixels: the filter window is (2r+1)^2 = 5x5
  float bilateralSpatialSigma = 4.0f;   // pixels
  float bilateralRangeSigma = 0.1f;     // metres
  float halfSampleMaxDifference = 0.3f; // metres: pyramid half-sampling keeps pixels this close to the centre

  // --- tracking (ICP) ---
  float icpDistanceThreshold = 0.1f;    // metres: pairs farther apart are rejected
  float icpNormalThreshold = 0.8f;      // cosine: pairs whose normals' dot product is lower are rejected
  float trackedMaxResidual = 0.02f;     // metres: RMS point-to-plane residual of a tracked frame
  float trackedMinInliers = 0.15f;      // fraction of the compute-size pixels that must be inliers
  int bootstrapFrames = 4;              // frames integrated at the initial pose before tracking starts
  // Smallest conditioning of the view's structure (pipeline/tracking_quality.h, blocks of qualityBlockPixels)
  // for a frame to count as "constrained": below it some motion is fixed by noise, not by the geometry in view.
  // Measured on synthetic Kinect-noise depth (README, Performance): stress-corridor's wall-only frames give at
  // most 0.0004 whatever the compute size and integration rate; the weakest furnished views 0.0001-0.0003
  // (a wall with a sliver of structure: those are flagged too), the 7-Scenes kitchen at least 0.01.
  float constrainedMinConditioning = 0.0003f;
  // Side, in sensor pixels, of the blocks whose rows are summed before the conditioning is taken
  // (pipeline/tracking_quality.h; at least one pixel of the tracked level): per-pixel normal noise falls by
  // about the block's inliers, structure larger than a block keeps its weight. 1: the per-pixel conditioning.
  int qualityBlockPixels = 32;

  // --- tracking state and relocalisation (runtime/tracking_monitor.h, reloc/) ---
  // Failed tracks in a row after which plain tracking is no longer trusted: the frames are lost until the
  // relocaliser confirms a pose (earlier failures keep the controller's bounded extrapolation).
  int lostAfterFailedFrames = 3;
  bool relocalise = true;               // try keyframe poses while lost (false: stay lost once lost)
  int relocaliseCandidates = 3;         // keyframes tried per lost frame (plus the last good pose)
  int relocaliseConfirmFrames = 3;      // consecutive frames a candidate must hold before it is accepted
  int relocaliseCsr = 2;                // compute size ratio of the relocaliser's ICP (1, 2, 4 or 8)
  // A candidate's ICP must pass the tracked tests, be constrained, and agree with this share of the pairs for
  // which the model has a surface (TrackAttempt::pairAgreement).
  float relocaliseMinPairAgreement = 0.87f;
  // The depth sensor's noise (pipeline/pair_noise.h): its disparity noise in its image's pixels (noise and
  // quantisation) and its baseline. When the noise is given (> 0) a relocalisation candidate's agreement counts
  // each pair within that noise at its range (TrackAttempt::agreementInNoise) instead of tracking's fixed tests.
  // 0: off (tracking's pair agreement).
  float depthNoiseDisparityPx = 0.0f;
  float depthNoiseBaselineM = 0.075f;
  // ... and at least the 90th percentile of the agreement of the last 300 good frames less this
  // (reloc/relocaliser.h; 1: off).
  float relocaliseAgreementMargin = 0.015f;
  // ... on a view whose structure conditioning is at least this (reloc/relocaliser.h).
  float relocaliseMinConditioning = 0.003f;
  float relocaliseMaxMotion = 0.1f;         // metres: motion between two confirming frames, at most
  float relocaliseMaxRotationDeg = 10.0f;   // degrees: the same for rotation
  int keyframeCapacity = 300;               // keyframes held (the oldest goes when full)
  float keyframeMinDissimilarity = 0.2f;    // a view unlike every keyframe by more than this becomes one
  // With a moving volume, the slabs that leave it are kept in memory, encoded, at most this many MiB (the oldest
  // dropped first), so that a lost run relocalises anywhere on its map, not only inside the volume
  // (runtime/map_store.h, MapStore::inMemory; docs/moving-volume.md). 0: none kept (the volume alone).
  int relocaliseKeptMapMib = 256;

  // --- volume (its size fixed per run; it may follow the camera) ---
  VolumeMode volumeMode = VolumeMode::automatic;  // Pipeline treats automatic as fixed
  // The moving volume shifts along an axis when the centre of the view (the point this far in front of the
  // camera along its optical axis, metres; 0: the camera itself) is farther than volumeShiftThreshold (metres)
  // from the volume's centre on that axis; the shift, whole blocks of 8 voxels, brings it back to the centre.
  float volumeViewDistance = 2.25f;
  float volumeShiftThreshold = 1.5f;
  int volumeResolution = 256;                           // voxels per side (multiple of 8)
  float volumeSize = 5.0f;                              // metres, side of the cube
  std::array<float, 3> initialPosition{0.5f, 0.5f, 0.3f};  // first camera position, fractions of the side
  // Whether volumeSize holds the sequence's hint (a cube that holds the whole path, for a fixed volume: 20.5 m for
  // a corridor drive) that no file or flag overrode. A moving volume follows the camera and keeps its own side
  // (runtime/run_setup.h, finishPipelineConfig); the hint's first position (fractions of the side) it keeps.
  struct VolumeHinted {
    bool size = false;
  } volumeHinted;
  float mu = 0.1f;                                      // metres: TSDF truncation distance
  int maxWeight = 100;                                  // maximum TSDF weight (frames)

  // --- raycast ---
  float nearPlane = 0.4f;               // metres (camera depth)
  float farPlane = 4.0f;                // metres (camera depth)
  float raycastLargeStep = 0.75f;       // in units of mu: step through free space
  float raycastSmallStep = 1.0f;        // in voxels: step near the surface
  float raycastSmallStepBelow = 0.8f;   // tsdf value under which the small step is used
  bool emptySpaceSkipping = true;       // jump over blocks that hold no surface (same surface, fewer samples)

  bool movesVolume() const { return volumeMode == VolumeMode::moving; }

  // --- render (output only) ---
  float renderAmbient = 0.1f;           // shade added to every lit pixel, [0, 1]

  // --- compute backend ---
  BackendKind backend = BackendKind::automatic;
  std::string openclPlatform;       // platform index ("0") or a name substring; empty: the first with a GPU
  std::string openclDevice;         // device index within the platform or a name substring; empty: first GPU
  bool openclHalfStorage = false;   // preprocessed and raycast maps stored as half (OpenCL only)
  std::string openclSourceDir;      // empty: the program embedded in the binary; else a directory holding
                                    // kernels/*.h and kernels/cl/*.cl to build instead (e.g. installed kernels)

  // --- initial knobs of a run ---
  Knobs knobs;

  float voxelSize() const { return volumeSize / static_cast<float>(volumeResolution); }  // metres
};

// Throws sb::Error naming the field, its value and the allowed range when a field is out of range.
void validateConfig(const PipelineConfig& config);

// Reads the JSON object `j` on top of `base`: keys are the snake_case field names with their unit, e.g.
// {"bilateral_range_sigma_m": 0.1, "volume_resolution": 256, "initial_position": [0.5, 0.5, 0.3],
//  "knobs": "csr=2,ir=1"}. Unknown keys, wrong types and out-of-range values throw sb::Error naming the key,
// the value and the allowed range. `where` (e.g. the file name) prefixes the messages.
PipelineConfig parseConfig(const nlohmann::json& j, const PipelineConfig& base = {}, const std::string& where = "config");

// Reads a JSON file (see parseConfig). Throws sb::Error naming the file on I/O and syntax errors.
PipelineConfig loadConfigFile(const std::string& path, const PipelineConfig& base = {});

// The whole config as JSON (the same keys parseConfig reads).
nlohmann::json configToJson(const PipelineConfig& config);

}  // namespace sb
