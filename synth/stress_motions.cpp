#include "synth/stress_motions.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "synth/builtin_trajectory.h"
#include "synth/stress_moves.h"

namespace sb::synth::stress {

namespace {

// Where the pan stands: in the free floor space of every generated room (the generator's camera space),
// 1-2 m from the furniture of the south-east corner, facing it. (From the built-in orbit's centre, 2.5 m
// away, ACCURATE's ICP jumped at 3 deg/frame: far points move past its 0.1 m correspondence threshold.)
const Eigen::Vector3d kPanBase(0.55, 0.0, -1.9);
constexpr double kPanYawRad = 0.75 * kPi;

// A stadium loop in the plan (x, z): straights along z at x0 (heading -z) and x1 (heading +z) from z0 to
// z1, joined by half circles. Arc length s runs counter-clockwise from (x1, z0), where the east straight
// starts.
struct Loop {
  double x0, x1, z0, z1;  // metres

  double radius() const { return 0.5 * (x1 - x0); }
  double straight() const { return z1 - z0; }
  double perimeter() const { return 2.0 * straight() + kTwoPi * radius(); }

  // 0 on the half circles, rising to 1 (minimum-jerk) over `blendM` metres of straight from either end.
  double straightShare(double s, double blendM) const {
    const double L = straight(), half = kPi * radius();
    s = std::fmod(s, perimeter());
    if (s < 0) s += perimeter();
    if (s >= L + half) s -= L + half;  // the west straight and the south half circle mirror the others
    if (s >= L) return 0.0;
    return minJerk(std::min(1.0, std::min(s, L - s) / blendM));
  }

  struct Point {
    Eigen::Vector2d position, heading;  // plan (x, z), metres; unit
    bool onArc;
  };
  Point at(double s) const {
    const double L = straight(), r = radius(), xc = 0.5 * (x0 + x1), half = kPi * r;
    s = std::fmod(s, perimeter());
    if (s < 0) s += perimeter();
    if (s < L) return {{x1, z0 + s}, {0.0, 1.0}, false};
    s -= L;
    if (s < half) {
      const double a = s / r;
      return {{xc + r * std::cos(a), z1 + r * std::sin(a)}, {-std::sin(a), std::cos(a)}, true};
    }
    s -= half;
    if (s < L) return {{x0, z1 - s}, {0.0, -1.0}, false};
    s -= L;
    const double a = kPi + s / r;
    return {{xc + r * std::cos(a), z0 + r * std::sin(a)}, {-std::sin(a), std::cos(a)}, true};
  }
};

// The first loop (largest first) that keeps the robot (a vertical cylinder of kRobotRadiusM up to the
// camera) clear of the walls and of every piece of furniture, low ones included.
Loop robotLoop(const Scene& scene, double cameraHeightM) {
  constexpr double kRobotRadiusM = 0.3;
  constexpr double kStepM = 0.05;
  constexpr double kMinRadiusM = 0.85;  // the half circles turn at under 71 deg/s at 1.05 m/s
  // Inside the generator's camera space (x -1.55..1.4, z -3..2.75), where only low furniture stands, around
  // the column at its north end; the largest first.
  std::vector<Loop> candidates;
  for (double x0 : {-1.15, -1.0, -0.85})
    for (double x1 : {1.0, 0.85, 0.7})
      for (int k = 0; k <= 10; ++k)
        for (double z1 : {1.6, 1.4})
          if (const double z0 = -1.7 + 0.28 * k; x1 - x0 >= 2.0 * kMinRadiusM && z0 <= z1)
            candidates.push_back({x0, x1, z0, z1});
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Loop& a, const Loop& b) { return a.perimeter() > b.perimeter(); });
  const double floorY = scene.roomMax.y();
  for (const Loop& loop : candidates) {
    bool clear = true;
    for (double s = 0.0; clear && s < loop.perimeter(); s += kStepM) {
      const Eigen::Vector2d q = loop.at(s).position;
      for (double h = 0.05; clear && h <= cameraHeightM + 1e-9; h += 0.25) {
        const Eigen::Vector3f p(static_cast<float>(q.x()), static_cast<float>(floorY - h),
                                static_cast<float>(q.y()));
        // (Walls in plan only: the floor is within the radius of the lowest points.)
        const Eigen::Vector3f wallCheck(p.x(), static_cast<float>(floorY - cameraHeightM), p.z());
        clear = scene.insideRoom(wallCheck, kRobotRadiusM) && scene.objectContaining(p, kRobotRadiusM) < 0;
      }
    }
    if (clear) return loop;
  }
  throw Error(
      "synth: --stress robot found no loop around the room's middle that keeps 0.3 m clear of the "
      "furniture in scene '" +
      scene.name + "' (seed " + std::to_string(scene.seed) + "); try another seed");
}

}  // namespace

StressTrajectory panTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr int kSweeps = 5;
  constexpr double kMinSweepRad = 80.0 * kDegToRad, kMaxSweepRad = 110.0 * kDegToRad;  // sweep widths
  constexpr double kStartHoldS = 1.0, kMinHoldS = 0.4, kMaxHoldS = 0.8;
  constexpr double kPitchJitterRad = 0.04;
  // Shares of the peak rate per sweep, shuffled: two sweeps reach it.
  double shares[kSweeps] = {1.0, 1.0, 0.9, 0.8, 0.7};
  for (int i = kSweeps - 1; i > 0; --i) std::swap(shares[i], shares[rng.index(i + 1)]);

  const Eigen::Vector3d base(kPanBase.x() + rng.uniform(-0.1f, 0.1f), eyeY(scene),
                             kPanBase.z() + rng.uniform(-0.1f, 0.1f));
  const double centre = kPanYawRad + rng.uniform(-0.1f, 0.1f);
  double side = rng.chance(0.5) ? 1.0 : -1.0;
  const CameraState start{base, centre - side * 0.5 * rng.uniform(kMinSweepRad, kMaxSweepRad),
                          kLevelPitchRad};
  std::vector<Move> moves{{"hold", kStartHoldS, start}};
  CameraState s = start;
  for (int k = 0; k < kSweeps; ++k) {
    CameraState target = s;
    target.yawRad = centre + side * 0.5 * rng.uniform(kMinSweepRad, kMaxSweepRad);
    target.pitchDownRad = kLevelPitchRad + rng.uniform(-kPitchJitterRad, kPitchJitterRad);
    const double rate = shares[k] * p.panRateDegps * kDegToRad;
    moves.push_back({"pan", kMinJerkPeak * std::abs(target.yawRad - s.yawRad) / rate, target});
    moves.push_back({"hold", rng.uniform(kMinHoldS, kMaxHoldS), target});
    s = target;
    side = -side;
  }
  return play(start, moves, p, rng);
}

StressTrajectory robotTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr double kRampS = 1.0;   // seconds to reach the cruise speed from rest, and to stop
  constexpr double kBlendM = 0.5;  // the speed changes between drive and turn over this much straight
  constexpr int kSubsteps = 20;    // per frame, integrating the speed along the path
  // Vibration of the chassis on the floor: amplitude and frequency of height, pitch and roll.
  constexpr double kVibrationM = 0.001, kVibrationRad = 0.002;
  constexpr double kVibrationHz[3] = {2.9, 2.3, 3.7};
  const Loop loop = robotLoop(scene, p.robotCameraHeightM);
  const double direction = rng.chance(0.5) ? 1.0 : -1.0;
  // Start on a straight, heading along it.
  const double startS = (rng.chance(0.5) ? 0.0 : loop.straight() + kPi * loop.radius()) +
                        (direction > 0 ? 0.0 : loop.straight()) + direction * rng.uniform(0.f, 0.5f);
  double phase[3];
  for (double& ph : phase) ph = rng.uniform(0.f, static_cast<float>(kTwoPi));
  auto vibration = [&](int axis, double t) {
    return std::sin(kTwoPi * kVibrationHz[axis] * t + phase[axis]);
  };
  // Speed along the path at time t and arc length s: the drive speed on the straights, the turn speed in
  // the half circles, ramped up from rest over the first kRampS and down to rest over the last.
  auto speed = [&](double t, double s) {
    const double ramp = minJerk(std::clamp(std::min(t, p.robotSeconds - t) / kRampS, 0.0, 1.0));
    const double w = loop.straightShare(startS + direction * s, kBlendM);
    return ramp * (p.robotTurnSpeedMps + w * (p.robotDriveSpeedMps - p.robotTurnSpeedMps));
  };

  const double cameraY = scene.roomMax.y() - p.robotCameraHeightM;
  const size_t frames = static_cast<size_t>(std::floor(p.robotSeconds * p.fps + 1e-9)) + 1;
  StressTrajectory out;
  out.poses.reserve(frames);
  double travelled = 0.0;
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / p.fps;
    if (i > 0) {
      const double dt = 1.0 / (p.fps * kSubsteps);
      for (int k = 0; k < kSubsteps; ++k) {  // midpoint steps
        const double tk = t - 1.0 / p.fps + k * dt;
        travelled += dt * speed(tk + 0.5 * dt, travelled + 0.5 * dt * speed(tk, travelled));
      }
    }
    std::string label = t < kRampS ? "start" : t > p.robotSeconds - kRampS ? "stop" : "";
    const Loop::Point q = loop.at(startS + direction * travelled);
    if (label.empty()) label = q.onArc ? "turn" : "drive";
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world.linear() =
        handheldRotation(yawOf(direction * q.heading), p.robotPitchDownRad + kVibrationRad * vibration(1, t),
                         kVibrationRad * vibration(2, t));
    pose.T_camera_to_world.translation() =
        Eigen::Vector3d(q.position.x(), cameraY + kVibrationM * vibration(0, t), q.position.y());
    out.poses.push_back(pose);
    if (out.segments.empty() || out.segments.back().label != label) out.segments.push_back({label, i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

}  // namespace sb::synth::stress
