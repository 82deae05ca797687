#pragma once
// The file names of a TUM-layout sequence directory, written once: what TumReader reads, TumWriter and
// `slambooster cut` write, and `slambooster synth` adds (docs/test-sequences.md).

namespace sb::tum {

inline constexpr const char* kIndexFile = "depth.txt";                // `timestamp depth/NNNNNN.png` per frame
inline constexpr const char* kAssociationsFile = "associations.txt";  // ICL-NUIM's index, read when depth.txt is absent
inline constexpr const char* kCalibrationFile = "calibration.json";   // intrinsics and depth scale
inline constexpr const char* kGroundTruthFile = "groundtruth.txt";    // TUM trajectory, camera-to-world
inline constexpr const char* kSegmentsFile = "segments.csv";          // a stress trajectory's named parts
inline constexpr const char* kDepthDir = "depth";                     // the PNGs TumWriter writes

}  // namespace sb::tum
