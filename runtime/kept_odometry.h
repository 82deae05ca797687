#pragma once
// The wheels' learnt calibration kept in a map store (issue 55; runtime/map_store.h, docs/map-store.md): what the
// odometry calibration (odometry/odometry_calibration.h: scale, turn scale, yaw drift, with the information that
// weighs them), the mount's correction (odometry/mount_calibration.h) and the odometry's clock
// (odometry/time_offset.h) learnt, so that the next run with odometry starts from them instead of the prior.
// odometry.bin is a state file of the store (runtime/map_store_format.h); its payload, little-endian, by version:
//   1: i32 calibration frames, f64 scale information, f64 scale vector, f64 yaw information[4] (row-major 2x2),
//      f64 yaw vector[2]; the mount's f64 view sum[3], wheel sum[3], difference sum[3], difference squares,
//      weights, weight squares, turn seen (rad), standard error (rad), correction[9] (row-major 3x3), i32 floor
//      frames, f64 floor spread (rad), i32 from the floor (0 or 1). 268 bytes.
//   2: version 1's, then the clock's f64 offset (s), i32 learnt (0 or 1), u64 frames of evidence; the mount the
//      correction was learnt against: i32 recorded (0 or 1), f64 up[3] (zero when not recorded). 316 bytes.
// A version-1 file is read as what it holds: no clock offset kept, no mount recorded (so its mount correction is
// not restored: runtime/run_map_store.cpp).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "odometry/mount_calibration.h"
#include "odometry/odometry_calibration.h"
#include "odometry/time_offset.h"

namespace sb {

struct KeptOdometry {
  odometry::CalibrationState calibration;
  odometry::MountCalibration::State mount;
  odometry::TimeOffset::State timeOffset;  // version 1: not kept (not learnt)
  // The mount the odometry assumed while the mount's correction was learnt: the odometry frame's up axis in the
  // camera frame (unit; T_camera_to_odom's rotation transposed times z, averaged over the frames the odometry
  // gave a pose): the configured mount's tilt, whatever door it came through (odometry.txt, a bag's /tf_static
  // or --camera-mount, the daemon's source.camera_mount). Absent: not recorded (version 1, or no pose seen).
  std::optional<Eigen::Vector3d> mountUp;
};

std::vector<uint8_t> encodeKeptOdometry(const KeptOdometry& kept);
// The payload of odometry.bin's `version` (1 or 2, mapstore::kOdometryFile). Throws sb::Error naming `path` when
// the payload is malformed (its size, a value not finite or out of its domain: an information that is not
// positive, a correction that is not a rotation).
KeptOdometry decodeKeptOdometry(const std::vector<uint8_t>& payload, const std::string& path, uint32_t version);

}  // namespace sb
