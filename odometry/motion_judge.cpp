// A tracked frame judged against the wheels (odometry/motion_model.h, judge): the inertia rule of one frame (the
// fault watch off) and the fault watch's evidence (odometry/wheel_faults.h).
#include <cmath>

#include "odometry/format_numbers.h"
#include "odometry/motion_model.h"

namespace sb::odometry {

void MotionModel::judgeByInertia(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion) {
  FrameResult& r = view.result;
  Decision& d = view.decision;
  if (r.tracked && motion.step) {
    // The view and the wheels are weighed first; where they disagree along a motion the view fixes, physics says
    // who is wrong: a tracked motion that departs further from the last velocity than the wheels' (inertia), or
    // one the platform cannot make, is the view's error (the pose follows the odometry); otherwise the wheels
    // slipped (the tracked pose stands).
    const Eigen::Isometry3d predicted = *motion.predicted();
    const Eigen::Isometry3d tracked = d.refinedPose ? *d.refinedPose : r.T_camera_to_world;
    const Fusion f = fuseWithOdometry(r.quality, motion.previousPose, tracked, predicted, *motion.step, config_,
                                      motion.level, takeFusedCovariance(motion));
    if (!f.rejected) {
      keepFusedCovariance(f, r.timestamp);
      view.odometry.used = true;
      if (motion.raw) calibration_.learn(r.quality, motion.previousPose, tracked, *motion.raw);
      d.refinedPose = f.pose;
      d.correctedPose.reset();  // a controller's extrapolation gives way to the wheels' word
      return;
    }
    view.odometry.rejected = true;
    view.odometry.why = f.why;
    if (d.correctedPose) return;
    const std::string inertia = viewBreaksInertia(motion.previousPose, tracked, predicted,
                                                  r.timestamp - motion.previousStamp, lastVelocity_, config_.slipFloorM);
    if (!inertia.empty())
      discardTrack(pipeline, view, motion, inertia);
    else
      checkPhysics(pipeline, view, motion);
    if (!r.tracked) {
      view.odometry.rejected = false;
      view.odometry.why.clear();
    }
  } else if (r.tracked && !d.correctedPose && motion.hasPrevious) {
    checkPhysics(pipeline, view, motion);
  }
}

void MotionModel::judgeAgainstWheels(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion,
                                     const std::optional<OdometryStep>& wheels) {
  FrameResult& r = view.result;
  Decision& d = view.decision;
  if (!held_) {
    // The view does not fit the map where it is tracked, whether or not the wheels agree with it: a robot set
    // down elsewhere whose view matched a look-alike near the wheels' pose, or a view that ran away. Nothing is
    // fused; the pose follows the wheels (within the dead-reckoning budget) while the evidence gathers.
    faults_.viewContradicted(r.timestamp);
    discardTrack(pipeline, view, motion, "the view does not fit the map where it is tracked (pair agreement " +
                                             formatNumbers("%.2f below %.2f)", r.pairAgreement, mapAgreement_.floor()));
    return;
  }
  if (!wheels) {  // a fault open and no odometry at this frame: the view alone
    if (!d.correctedPose && motion.hasPrevious) checkPhysics(pipeline, view, motion);
    return;
  }
  const Eigen::Isometry3d predicted = motion.previousPose * wheels->delta;
  const Eigen::Isometry3d tracked = d.refinedPose ? *d.refinedPose : r.T_camera_to_world;
  // The view's rotation since it last fixed the pose, where it fixes every rotation: the evidence of the
  // odometry's clock (whether or not the wheels agree: a latency is what makes them disagree in a turn).
  if (lastViewPose_ && r.quality.known && r.quality.constrained) {
    const Eigen::AngleAxisd turn(lastViewPose_->linear().transpose() * tracked.linear());
    timeOffset_.add(*track_, lastViewStamp_, r.timestamp, turn.axis() * turn.angle());
  }
  Fusion f = fuseWithOdometry(r.quality, motion.previousPose, tracked, predicted, *wheels, config_, motion.level,
                              takeFusedCovariance(motion));
  if (!f.rejected) {  // each frame within the gate, but the same turn error frame after frame: contradicted all the same
    const Eigen::AngleAxisd turn(f.viewed.linear() * predicted.linear().transpose());
    const std::string sustained = turnCorrections_.add(r.timestamp, turn.axis() * turn.angle(), wheels->sigmaRad,
                                                       config_.slipSigmas, config_.slipFloorM);
    if (!sustained.empty()) {
      f.rejected = true;
      f.why = sustained;
    } else if (viewMet_ && (tracked.translation() - predicted.translation()).norm() > config_.slipFloorM) {
      f.rejected = true;
      f.why = formatNumbers("the view tracked to one pose from the wheels' prediction and its own: it fixes the "
                            "motion, and the wheels' prediction is %.3f m from it",
                            (tracked.translation() - predicted.translation()).norm());
    }
  }
  if (f.rejected) {
    // A motion the platform cannot make is the view's error (a runaway along a wall), whoever disagrees with it.
    // The view tracked from its own prediction was held to the platform's physics from the view's last pose.
    if (!d.correctedPose && !viewPredicted_) checkPhysics(pipeline, view, motion);
    if (!r.tracked) {
      faults_.interrupt();
      return;
    }
    disputedAlong(tracked, predicted);
    // A body keeps its velocity: a view that departs further from the last velocity than the wheels' step (it
    // slid to a look-alike of the corridor by a door's spacing) is discarded for this frame, as a wheel step that
    // jumps is. One frame's inertia cannot decide a fault that lasts, though: after a discarded view the last
    // velocity is the wheels', and a stall's view (tracked from the wheels' prediction each frame) is discarded
    // again and again while the map grows at the wheels' poses. So a correction the view asks for that keeps
    // growing frame after frame is the wheels running away: the view's pose stands (wheel_faults.h diverging); and
    // one that stays the same frame after frame is the view moving as the wheels do from where the map puts the
    // camera (the way back meeting the way out's map, offset by drift): the view's pose stands too (steady).
    // Either way a dispute opens: nothing is fused and no pose is good until the evidence decides it.
    // A view that stands where it last fixed the pose while the wheels drove on is a stall (the robot ran into
    // something and its wheels spin): a sudden stop is a motion a body makes, and the view is no look-alike
    // (one would not land on the very pose it left), so inertia does not discard it; it is the evidence.
    // The view tracked from its own prediction holds the map better than from the wheels': it kept the body's
    // inertia as the view measured it, and the wheels' prediction is what departed from it.
    if (!motion.withheld && !viewPredicted_ && !viewStill(tracked, motion, *wheels)) {
      const std::string inertia = viewBreaksInertia(motion.previousPose, tracked, predicted,
                                                    r.timestamp - motion.previousStamp, lastVelocity_,
                                                    config_.slipFloorM);
      const double dt = r.timestamp - motion.previousStamp;
      const bool withinReach = (tracked.translation() - motion.previousPose.translation()).norm() <=
                               (lastVelocity_ ? lastVelocity_->linear.norm() * dt : 0.0) + config_.slipFloorM;
      if (!inertia.empty() && !faults_.diverging(r.timestamp, f.disagreementM, withinReach) &&
          !steadyCorrection(r.timestamp, tracked, predicted, motion, *wheels)) {
        discardTrack(pipeline, view, motion, inertia);
        return;
      }
    }
    faults_.wheelsContradicted(r.timestamp);
    view.odometry.rejected = true;
    view.odometry.why = f.why;
  } else if (settles(r.quality)) {
    faults_.agreed(r.timestamp);
  }
  if (motion.withheld) {  // slipping: the wheels are watched, not used; the view alone, as without odometry
    if (!f.rejected && !d.correctedPose && motion.hasPrevious) checkPhysics(pipeline, view, motion);
    return;
  }
  if (f.rejected) {
    d.integrate = false;  // the frame disagrees with the wheels: it does not feed the map until that is decided
    return;
  }
  view.odometry.used = true;
  keepFusedCovariance(f, r.timestamp);
  if (motion.raw) calibration_.learn(r.quality, motion.previousPose, tracked, *motion.raw);
  if (learnsMount() && motion.reported && r.quality.known && r.quality.constrained)  // a view fixing every rotation
    mount_.learn(motion.previousPose.linear().transpose() * tracked.linear(), *motion.reported);
  d.refinedPose = f.pose;
  d.correctedPose.reset();  // a controller's extrapolation gives way to the wheels' word
}

void MotionModel::disputedAlong(const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& predicted) {
  const Eigen::Vector3d offset = tracked.translation() - predicted.translation();
  if (offset.norm() > kStillM) disputed_ = offset.normalized();
}

bool MotionModel::settles(const TrackingQuality& quality) const {
  // Only a view that fixes the motion the dispute is about can agree with the wheels on it: along a motion it
  // leaves free (a corridor's axis) ICP stays where the wheels' prediction started it, and that is no agreement
  // (held-out drives with wheels reading zero, or half the distance: three such frames ended the dispute, and the
  // pose the wheels had carried 0.3-0.6 m along the corridor was `good` from there on).
  if (faults_.fault() != WheelFault::disputed || !disputed_ || !quality.known) return true;
  Twist along = Twist::Zero();
  along.head<3>() = *disputed_;
  return conditioningAlong(quality, along) >= config_.minConditioning;
}

std::optional<Eigen::Isometry3d> MotionModel::viewPrediction(double stamp) const {
  const double dt = stamp - agreedStamp_;
  if (!agreedPose_ || !viewVelocity_ || !(dt > 0) || dt > kViewPredictionS) return std::nullopt;
  Eigen::Isometry3d pose = *agreedPose_;
  pose.translation() += viewVelocity_->linear * dt;
  const double turn = viewVelocity_->angular.norm() * dt;
  if (turn > 0) pose.linear() = pose.linear() * Eigen::AngleAxisd(turn, viewVelocity_->angular.normalized()).matrix();
  return pose;
}

bool MotionModel::trackFromViewMotion(Pipeline& pipeline, const FrameView& view, const FrameMotion& motion) {
  FrameResult& r = view.result;
  if (!view.trackFrom || !motion.step || !r.trackingAttempted) return false;
  const std::optional<Eigen::Isometry3d> own = viewPrediction(r.timestamp);
  if (!own) return false;
  // Wheels that go wrong (reversed, a gyro's bias, a stall) carry the frames they predict away from where the
  // body's inertia takes it, and ICP from there settles where the view fixes least (along a corridor) or fails: the
  // view then seems to agree with them, or to be lost, while its own motion of the frames before would have
  // tracked it. So a frame in doubt is tracked from both predictions, and the map decides between them.
  const Eigen::Isometry3d wheels = *motion.predicted();
  const double apartM = (own->translation() - wheels.translation()).norm();
  const double apartDeg = Eigen::AngleAxisd(own->linear().transpose() * wheels.linear()).angle() * 180.0 / M_PI;
  const bool doubt = !r.tracked || !mapAgreement_.holds(r.pairAgreement) || faults_.fault() != WheelFault::none;
  if (!doubt && apartM <= kPredictionsApartM && apartDeg <= kPredictionsApartDeg) return false;
  const TrackAttempt ownTrack = view.trackFrom(*own);
  view.decision.keepReference = false;  // the reference now shows the view's prediction
  // The map decides where it tells the two apart. Where it cannot (both hold it within the margin: a corridor's
  // axis, along which ICP leaves either prediction in place) and the two dispute the motion, the body's inertia as
  // the view measured it does: a held-out drive with wheels reading zero while the robot drove on had the view stop
  // with them, agreeing with the map as well (0.87 against 0.88), and its velocity then stopped the view's
  // prediction too.
  // Both tracked to one pose from starts farther apart than a slip: the view fixes the motion between them, whatever
  // its conditioning says (wheels reading zero on a drive: the tracks from both predictions, 3.6 cm apart, met
  // within 2 mm, and the fusion still took the wheels' word along the corridor's axis, taken for one the view
  // leaves free: 7 `good` frames 0.5 m off, DEFAULT).
  const double metM = (ownTrack.T_camera_to_world.translation() - r.T_camera_to_world.translation()).norm();
  const double metDeg =
      Eigen::AngleAxisd(ownTrack.T_camera_to_world.linear().transpose() * r.T_camera_to_world.linear()).angle() *
      180.0 / M_PI;
  viewMet_ = r.tracked && ownTrack.tracked && apartM > config_.slipFloorM && metM <= kTracksMetM &&
             metDeg <= kTracksMetDeg;
  const double margin = config_.jumpAgreementMargin;
  const bool wheelsHold = r.tracked && mapAgreement_.holds(r.pairAgreement);
  const bool ownHolds = ownTrack.tracked && mapAgreement_.holds(ownTrack.pairAgreement);
  // The two tracks apart: ICP left each near its start (within a few centimetres of each other it converged, and the
  // better agreement stands).
  const Eigen::Isometry3d& wheelsTrack = r.T_camera_to_world;
  const bool tracksApart =
      (ownTrack.T_camera_to_world.translation() - wheelsTrack.translation()).norm() > config_.slipFloorM ||
      Eigen::AngleAxisd(ownTrack.T_camera_to_world.linear().transpose() * wheelsTrack.linear()).angle() >
          config_.slipFloorM;
  const bool adopt = ownHolds && (!wheelsHold || ownTrack.pairAgreement >= r.pairAgreement + margin ||
                                  (faults_.fault() != WheelFault::none && tracksApart &&
                                   ownTrack.pairAgreement > r.pairAgreement - margin));
  if (!adopt) return false;
  // The view confirmed its own prediction where it made it (ICP moved it less than a slip): a view that matched the
  // model elsewhere (a runaway along the corridor, 0.07-0.22 m from its start) is no evidence against the wheels.
  const Eigen::Isometry3d& found = ownTrack.T_camera_to_world;
  if ((found.translation() - own->translation()).norm() > config_.slipFloorM ||
      Eigen::AngleAxisd(found.linear().transpose() * own->linear()).angle() > config_.slipFloorM)
    return false;
  const double wheelsAgreement = r.tracked ? r.pairAgreement : 0.0;
  pipeline.adoptAttempt(ownTrack, r);
  view.decision.correctedPose.reset();
  view.decision.refinedPose.reset();
  viewPredictedWhy_ = formatNumbers("tracked from the view's own motion: it holds the map (pair agreement %.2f against "
                                    "%.2f from the wheels' prediction, %.3f m and %.1f deg apart)",
                                    ownTrack.pairAgreement, wheelsAgreement, apartM, apartDeg);
  return true;
}

std::optional<Matrix6> MotionModel::takeFusedCovariance(const FrameMotion& motion) {
  std::optional<Matrix6> out;
  if (fusedCovariance_ && motion.hasPrevious && fusedStamp_ == motion.previousStamp) out = fusedCovariance_;
  fusedCovariance_.reset();
  return out;
}

void MotionModel::keepFusedCovariance(const Fusion& fused, double stamp) {
  fusedCovariance_ = fused.covariance;
  fusedStamp_ = stamp;
}

bool MotionModel::steadyCorrection(double stamp, const Eigen::Isometry3d& tracked, const Eigen::Isometry3d& predicted,
                                   const FrameMotion& motion, const OdometryStep& wheels) {
  // Where the view puts the camera against where the wheels do: the camera centre's offset and the turn, both in
  // the world frame (a map offset by drift keeps both while the robot drives on).
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  correction.linear() = tracked.linear() * predicted.linear().transpose();
  correction.translation() = tracked.translation() - predicted.translation();
  // As far as the wheels' pose may be off the map: the tolerance a relocalisation is held to (vet).
  const double reachM = config_.relocaliseToleranceM + config_.noisePerM * motion.uncheckedM;
  return faults_.steady(stamp, correction, kStillM + wheels.sigmaM, correction.translation().norm() <= reachM);
}

bool MotionModel::viewStill(const Eigen::Isometry3d& tracked, const FrameMotion& motion,
                            const OdometryStep& wheels) const {
  if (!lastViewPose_) return false;
  // The wheels' motion since the view last fixed the pose: this step, or the whole unchecked interval.
  const double wheelsM = std::max(wheels.distanceM(), motion.uncheckedM);
  const double viewM = (tracked.translation() - lastViewPose_->translation()).norm();
  const double viewDeg =
      Eigen::AngleAxisd(lastViewPose_->linear().transpose() * tracked.linear()).angle() * 180.0 / M_PI;
  return viewM <= kStillM && viewDeg <= kStillDeg && wheelsM >= 2.0 * kStillM;
}

}  // namespace sb::odometry
