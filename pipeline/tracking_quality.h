#pragma once
// Tracking quality: how well the geometry in view fixes the camera's motion (issue 21, architecture.md D4).
//
// Point-to-plane ICP constrains a motion only along the normals it sees: in front of one plane (a blank wall)
// it cannot see sliding along the plane or turning about its normal, and it "converges" there to whatever
// the noise suggests. The 6x6 normal matrix J^T J of the last ICP pass says which motions are fixed:
//   - rotations are taken about the camera centre (not the volume origin), so the number does not depend on
//     where the volume happens to be;
//   - the rotational columns are scaled so that the rotational block carries the same trace as the
//     translational one (which is the inlier count, since normals have unit length): translation and rotation
//     then weigh alike whatever the scene's depth, and the result is scale-free;
//   - divided by the inlier count, the matrix has trace 2 and its smallest eigenvalue is the mean squared
//     share of a point's constraint that lies along the weakest motion: 0 for an exactly unconstrained motion,
//     1/3 at most (three orthogonal planes seen alike).
// Normal noise puts a floor under that number: in front of a plane, the in-plane part of every measured normal
// constrains the sliding a little, by its variance. The floor is the model's noise (the reference normals are
// raycast from the TSDF), so it rises when fewer frames are fused: on stress-corridor's wall-only frames from
// at most 0.0004 when every frame is integrated to 0.0025 when one in eight is, above the weakest furnished
// views (0.001). So the reported "conditioning" is that of the view's structure: the same matrix with the rows
// of each block of `block` x `block` pixels summed first (ComputeBackend::blockSums): structure is coherent
// over a block and keeps its weight, independent noise averages out (its share falls by the block's inliers).
// The per-pixel value stays as "ICP conditioning" (what the adaptive controller's doubt reads).
// A frame is "constrained" when its conditioning is at least PipelineConfig::constrainedMinConditioning.

#include <Eigen/Geometry>
#include <string>

#include "pipeline/backend.h"
#include "pipeline/icp_solve.h"

namespace sb {

// The weakest motion, in camera axes (x right, y down, z forward): translation along or rotation about one.
enum class WeakDirection { tx, ty, tz, rx, ry, rz };
const char* weakDirectionName(WeakDirection d);  // "tx", "ty", "tz", "rx", "ry", "rz"

struct TrackingQuality {
  bool known = false;          // false when no ICP pass ran (bootstrap frames, frames skipped by tr)
  double conditioning = 0.0;     // of the view's structure (block rows, see above), [0, 1/3]
  double icpConditioning = 0.0;  // of the per-pixel ICP normal matrix, [0, 1/3]
  WeakDirection weakest = WeakDirection::tx;  // the camera axis the structure's weakest motion lies along most
  bool constrained = true;     // conditioning >= the configured minimum (true when not known)
  // The structure's normal matrix (block rows, per inlier) in the motion basis, and that basis: a twist x in
  // the world frame (icp_solve.h) is basis * x_n. Zero when not known.
  Matrix6 structure = Matrix6::Zero();
  Matrix6 basis = Matrix6::Identity();
};

// A motion learnt from a frame, kept only as far as the view fixed it: along each eigenvector of the structure
// with eigenvalue (conditioning) c, the result moves from `previous` towards `measured` by c / (c + lambda).
// Along a motion the view leaves free, ICP returns its start pose plus a slide; the start is the prediction,
// so learning the slide whole makes the prior a random walk along that motion (a robot stopping before a bare
// end wall: 5 cm/frame upwards within 15 frames). lambda <= 0 or quality not known: `measured`.
Twist blendByStructure(const TrackingQuality& quality, const Twist& previous, const Twist& measured, double lambda);

// The quality of the ICP problem whose reduced sums are `icp` (kernels/track.h layout, Jacobian columns in the
// volume frame) and whose block sums are `blocks` (ComputeBackend::blockSums of the same pass), solved around
// the camera pose `T_camera_to_world`. `minConditioning`: the constrained threshold. Fewer than kMinIcpInliers
// inliers or a non-finite matrix give conditioning 0, not constrained.
TrackingQuality trackingQuality(const TrackSums& icp, const TrackSums& blocks,
                                const Eigen::Isometry3d& T_camera_to_world, double minConditioning);

}  // namespace sb
