#pragma once
// The wheels' systematic errors, learnt online from the view (docs/odometry.md). A base's odometry is off by
// more than noise: a wheel radius a few percent from its nominal value reads every metre long or short, a
// gyro's bias turns the heading at rest, and turns read large or small. Fused frame by frame, such an error
// passes straight into the pose along every motion the view leaves free (a corridor seen lengthwise), and it
// is the same on every metre, so it adds up. Where the view does fix a motion, ICP measures the truth of the
// wheels' step along it: three numbers are estimated from those frames by recursive least squares (after the
// odometry calibration of e.g. Censi, Franchi, Marchionni and Oriolo, IEEE T-RO 2013, here online and against
// the tracker instead of a reference):
//   scale      the distance driven reads (1 + scale) times the truth
//   yawScale   a turn about the odometry's up axis reads (1 + yawScale) times the truth ...
//   yawBias    ... plus yawBias rad/s of drift, at rest too
// Each observation weighs by how well the view fixes that motion (its conditioning, tracking_quality.h) against
// ICP's and the odometry's stated noise; a zero-mean prior of a few percent (a base that far off is broken)
// keeps the estimate at zero until the evidence outweighs it, and evidence older than the window (distance,
// time) fades: wheels wear, loads and floors change, a gyro's bias follows its temperature. Every step the
// runtime takes from the odometry is corrected by the estimate (the ICP start, the fusion, dead reckoning).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "odometry/odometry_config.h"
#include "pipeline/tracking_quality.h"
#include "odometry/odometry_fusion.h"

namespace sb::odometry {

struct CalibrationEstimate {
  double scale = 0.0;         // the distance reads (1 + scale) times the truth
  double yawScale = 0.0;      // turns read (1 + yawScale) times the truth ...
  double yawBiasRadPerS = 0.0;  // ... plus this drift
  // Standard deviations of the three (from the prior and the evidence): how sure the estimate is.
  double scaleSigma = 0.0, yawScaleSigma = 0.0, yawBiasSigmaRadPerS = 0.0;
  int frames = 0;             // frames that brought evidence
};

// What the estimate has learnt, whole: the information (inverse covariance) of the wheels' excess reading and
// its information vector, the prior's included (a map store keeps it for the next run, runtime/kept_odometry.h).
struct CalibrationState {
  double scaleInfo = 0.0, scaleVec = 0.0;
  Eigen::Matrix2d yawInfo = Eigen::Matrix2d::Zero();  // of (yawScale, yawBias)
  Eigen::Vector2d yawVec = Eigen::Vector2d::Zero();
  int frames = 0;
};

class OdometryCalibration {
 public:
  explicit OdometryCalibration(const OdometryConfig& config);
  // The wheels' step with the estimate's errors taken out (unchanged when calibration is off).
  OdometryStep correct(const OdometryStep& raw) const;
  // A tracked frame the odometry was fused with: `previous` the last frame's final pose, `tracked` ICP's pose
  // (before fusion), `raw` the uncorrected step between them.
  void learn(const TrackingQuality& quality, const Eigen::Isometry3d& previous, const Eigen::Isometry3d& tracked,
             const OdometryStep& raw);
  CalibrationEstimate estimate() const;
  bool enabled() const { return config_.calibrationWindowM > 0.0; }
  // The learnt state, and a start from one (an earlier run's: its evidence fades as this run's comes in).
  CalibrationState state() const { return {scaleInfo_, scaleVec_, yawInfo_, yawVec_, frames_}; }
  void restore(const CalibrationState& s);

 private:
  // Internally the wheels' reading exceeds the truth by a fraction of the reading: truth = reading * (1 - scale),
  // turn = reading * (1 - yawScale) - yawBias * dt (linear in what is regressed on: the reading).
  struct Excess {
    double scale = 0.0, yawScale = 0.0, yawBiasRadPerS = 0.0;
  };
  Excess excess() const;  // bounded

  OdometryConfig config_;
  // Information (inverse covariance) and information vector of the scale (1-D) and of (yawScale, yawBias) (2-D),
  // the prior's included.
  double scaleInfo_, scaleVec_ = 0.0;
  Eigen::Matrix2d yawInfo_;
  Eigen::Vector2d yawVec_ = Eigen::Vector2d::Zero();
  int frames_ = 0;
};

}  // namespace sb::odometry
