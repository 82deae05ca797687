#include "synth/stress_trajectory.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/rng.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"

namespace sb::synth {

namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kMinJerkPeak = 1.875;  // peak of d/dtau of the minimum-jerk profile 10t^3 - 15t^4 + 6t^5
constexpr double kEyeHeightM = 1.35;    // camera height above the floor, metres (as the ICL-NUIM cameras)
constexpr double kLevelPitchRad = 0.2;  // usual downward tilt of a handheld camera
// Hand-sway frequencies (Hz), incommensurate: x, y, z, yaw, pitch, roll.
constexpr double kSwayHz[6] = {0.37, 0.27, 0.21, 0.16, 0.23, 0.33};

struct CameraState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // metres, world
  double yawRad = 0.0;                                 // forward (sin yaw, 0, cos yaw) before pitch
  double pitchDownRad = kLevelPitchRad;
};

// A minimum-jerk move from the previous state to `target` over `durationS` seconds.
struct Move {
  const char* label;
  double durationS;
  CameraState target;
};

double minJerk(double tau) {
  return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}

CameraState lerp(const CameraState& a, const CameraState& b, double s) {
  return {a.position + s * (b.position - a.position), a.yawRad + s * (b.yawRad - a.yawRad),
          a.pitchDownRad + s * (b.pitchDownRad - a.pitchDownRad)};
}

// Samples the moves at `fps` (frame i at t = i / fps, the last frame at the end of the last move) and adds
// the hand sway (seeded phases).
StressTrajectory play(const CameraState& start, const std::vector<Move>& moves, const StressParams& p,
                      Rng& rng) {
  double total = 0.0;
  for (const Move& m : moves) total += m.durationS;
  const size_t frames = static_cast<size_t>(std::floor(total * p.fps + 1e-9)) + 1;
  double phase[6];
  for (double& ph : phase) ph = rng.uniform(0.f, static_cast<float>(kTwoPi));
  auto sway = [&](int axis, double t) { return std::sin(kTwoPi * kSwayHz[axis] * t + phase[axis]); };

  StressTrajectory out;
  out.poses.reserve(frames);
  CameraState from = start;
  size_t move = 0;
  double moveStart = 0.0;
  for (size_t i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / p.fps;
    while (move + 1 < moves.size() && t >= moveStart + moves[move].durationS) {
      from = moves[move].target;
      moveStart += moves[move].durationS;
      ++move;
    }
    const double tau = std::clamp((t - moveStart) / moves[move].durationS, 0.0, 1.0);
    const CameraState s = lerp(from, moves[move].target, minJerk(tau));
    TimedPose pose;
    pose.timestamp = t;
    pose.T_camera_to_world.linear() =
        handheldRotation(s.yawRad + p.swayAngleRad * sway(3, t), s.pitchDownRad + p.swayAngleRad * sway(4, t),
                         p.swayAngleRad * sway(5, t));
    pose.T_camera_to_world.translation() =
        s.position + p.swayPositionM * Eigen::Vector3d(sway(0, t), sway(1, t), sway(2, t));
    out.poses.push_back(pose);
    const std::string label = moves[move].label;
    if (out.segments.empty() || out.segments.back().label != label) out.segments.push_back({label, i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

// Camera right (image +x) in the horizontal plane for a camera facing `yaw`.
Eigen::Vector3d lateralOf(double yaw) {
  return {std::cos(yaw), 0.0, -std::sin(yaw)};
}

double signTowards(double offset, Rng& rng) {
  if (std::abs(offset) > 1e-9) return offset > 0 ? -1.0 : 1.0;
  return rng.chance(0.5) ? 1.0 : -1.0;
}

StressTrajectory burstsTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr int kBursts = 4;
  constexpr double kCalmDriftM = 0.08, kCalmDriftRad = 0.2, kCalmDriftPitchRad = 0.06;
  constexpr double kMaxOffsetM = 0.35, kMaxYawOffsetRad = 0.6;
  constexpr double kFinalCalmS = 2.0;
  // The built-in orbit's centre: free floor space in every generated room; facing the south-east corner.
  const Eigen::Vector3d base(0.0, scene.roomMax.y() - kEyeHeightM, -1.2);
  const double baseYaw = 0.75 * kPi;
  // A minimum-jerk move of d over T peaks at 1.875 d / T: the moves that peak at the set speed and rate.
  const double burstShift = p.burstSpeedMps * p.burstDurationS / kMinJerkPeak;
  const double burstTurn = p.burstRateDegps * kPi / 180.0 * p.burstDurationS / kMinJerkPeak;

  // Every burst moves and turns at once; the shares are of the peak speed and rate.
  struct BurstKind {
    double speedShare, rateShare;
    enum { Sideways, Forward } direction;  // of the translation, in the camera's horizontal plane
    enum { Against, With, Pitch } turn;    // yaw against / with a sideways move (forward: seeded), or pitch
  };
  const BurstKind kinds[kBursts] = {
      {1.0, 0.55, BurstKind::Sideways, BurstKind::Against},  // a sideways jerk, turning to keep the view
      {0.75, 0.9, BurstKind::Sideways, BurstKind::With},     // a swing: the view sweeps fast
      {0.45, 1.0, BurstKind::Forward, BurstKind::With},      // a yaw flick with a step
      {0.55, 0.85, BurstKind::Forward, BurstKind::Pitch},    // a nod with a lunge
  };
  std::vector<int> order{0, 1, 2, 3};
  for (int i = kBursts - 1; i > 0; --i)
    std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(rng.index(i + 1))]);

  CameraState start{base + Eigen::Vector3d(rng.uniform(-0.1f, 0.1f), 0.0, rng.uniform(-0.1f, 0.1f)),
                    baseYaw + rng.uniform(-0.2f, 0.2f), kLevelPitchRad};
  CameraState s = start;
  std::vector<Move> moves;
  auto clampToBase = [&](CameraState& c) {
    Eigen::Vector3d offset = c.position - base;
    if (offset.norm() > kMaxOffsetM) c.position = base + offset.normalized() * kMaxOffsetM;
    c.yawRad = std::clamp(c.yawRad, baseYaw - kMaxYawOffsetRad, baseYaw + kMaxYawOffsetRad);
  };
  for (int b = 0; b < kBursts; ++b) {
    CameraState calm = s;
    calm.position +=
        Eigen::Vector3d(rng.uniform(-kCalmDriftM, kCalmDriftM), 0.0, rng.uniform(-kCalmDriftM, kCalmDriftM));
    calm.yawRad += rng.uniform(-kCalmDriftRad, kCalmDriftRad);
    calm.pitchDownRad = kLevelPitchRad + rng.uniform(-kCalmDriftPitchRad, kCalmDriftPitchRad);
    clampToBase(calm);
    moves.push_back(
        {"calm", rng.uniform(static_cast<float>(p.calmMinS), static_cast<float>(p.calmMaxS)), calm});

    const BurstKind& kind = kinds[order[static_cast<size_t>(b)]];
    const Eigen::Vector3d lateral = lateralOf(calm.yawRad);
    const Eigen::Vector3d forward(std::sin(calm.yawRad), 0.0, std::cos(calm.yawRad));
    const Eigen::Vector3d axis = kind.direction == BurstKind::Sideways ? lateral : forward;
    const double shiftSign = signTowards((calm.position - base).dot(axis), rng);  // back towards the base
    CameraState burst = calm;
    burst.position += shiftSign * kind.speedShare * burstShift * axis;
    const double turn = kind.rateShare * burstTurn;
    switch (kind.turn) {
      case BurstKind::Against:  // moving right (+lateral) while turning left (-yaw) keeps the view
        burst.yawRad -= shiftSign * turn;
        break;
      case BurstKind::With:
        burst.yawRad +=
            (kind.direction == BurstKind::Sideways ? shiftSign : signTowards(calm.yawRad - baseYaw, rng)) *
            turn;
        break;
      case BurstKind::Pitch:
        burst.pitchDownRad += signTowards(calm.pitchDownRad - kLevelPitchRad, rng) * turn;
        break;
    }
    moves.push_back({"burst", p.burstDurationS, burst});
    s = burst;
  }
  CameraState last = s;
  last.position = 0.5 * (s.position + base);
  last.yawRad = 0.5 * (s.yawRad + baseYaw);
  last.pitchDownRad = kLevelPitchRad;
  moves.push_back({"calm", kFinalCalmS, last});
  return play(start, moves, p, rng);
}

// How good a furnished view is: -1 when under 85% of the pixels have a reading (out of sensor range); else
// its depth structure (the smallest depth std over the detector's windows, metres), plus 10 when ICP sees
// every motion well (so those views win).
double furnishedScore(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world) {
  constexpr double kMinValid = 0.85, kWellConstrained = 0.02, kConstrainedBonus = 10.0;
  const ViewMetrics m = measureView(renderer, T_camera_to_world);
  if (m.validFraction < kMinValid) return -1.0;
  return m.minWindowStdM + (m.minConstraint >= kWellConstrained ? kConstrainedBonus : 0.0);
}

Eigen::Isometry3d poseOf(const CameraState& s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = handheldRotation(s.yawRad, s.pitchDownRad, 0.0);
  T.translation() = s.position;
  return T;
}

// Yaw of a camera looking along the plan direction `d` (x, z).
double yawOf(const Eigen::Vector2d& d) {
  return std::atan2(d.x(), d.y());
}

// The blank-wall view: facing a blank stretch that ends at a room corner, from where the detector's windows
// see only the blank wall (every window's depth std small) while the image border, outside the windows,
// holds the side wall of the corner and the floor: three plane orientations, so ICP sees every motion.
struct CornerView {
  CameraState blank;             // the view held while facing the blank wall
  std::vector<CameraState> pan;  // the slow pan's key states around it (all checked like `blank`)
  CameraState stand;             // further back into the room, where the turns happen
  Eigen::Vector2d inward;        // the blank wall's inward normal (plan x, z)
  double worstStdM = 1e9, constraint = -1.0;
};

CornerView cornerView(const Scene& scene, const StressParams& p) {
  constexpr double kCornerSlackM = 0.25;    // a stretch ends at a corner when the side wall is this close
  constexpr double kMaxWindowStdM = 0.085;  // the detector's threshold is 0.14 m: margin for noise and sway
  constexpr double kMinValid = 0.9;
  constexpr double kFreeM = 0.3;       // cameras keep this far from walls and furniture while placed
  constexpr double kStandBackM = 0.6;  // the stand is this much further from the wall
  constexpr double kPanTowardM = 0.05, kPanYawRad = 0.03, kPanPitchRad = 0.03;
  constexpr int kProbeScale = 8;
  const double distances[] = {1.0, 1.15, 1.3, 1.45, 1.6, 1.75};  // from the blank wall, metres
  const double sideRatios[] = {0.45, 0.5, 0.55, 0.6, 0.65};      // side-wall distance / wall distance
  const double yawOffsets[] = {-0.1, -0.05, 0.0, 0.05, 0.1};     // towards the corner, radians
  const double pitches[] = {0.3, 0.35, 0.4, 0.45, 0.5};          // downwards, radians
  const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
  const float eye = scene.roomMax.y() - static_cast<float>(kEyeHeightM);
  auto free = [&](const Eigen::Vector2d& q) {
    const Eigen::Vector3f at(static_cast<float>(q.x()), eye, static_cast<float>(q.y()));
    return scene.insideRoom(at, kFreeM) && scene.objectContaining(at, kFreeM) < 0;
  };
  auto state = [&](const Eigen::Vector2d& q, double yaw, double pitch) {
    return CameraState{Eigen::Vector3d(q.x(), eye, q.y()), yaw, pitch};
  };

  CornerView best;
  for (const BlankWall& wall : scene.blankWalls) {
    const Eigen::Vector2d from = wall.from.cast<double>(), to = wall.to.cast<double>();
    const Eigen::Vector2d inward = wall.inward.cast<double>(), along = (to - from).normalized();
    // The room corner on this wall's line, beyond the end of the stretch nearest to it.
    const Eigen::Vector2d lo(scene.roomMin.x(), scene.roomMin.z()), hi(scene.roomMax.x(), scene.roomMax.z());
    // How far `end` is from the side wall, going along the wall in direction dir * along.
    auto sideGap = [&](const Eigen::Vector2d& end, double dir) {
      const Eigen::Vector2d d = dir * along;
      double gap = 1e9;
      for (int a = 0; a < 2; ++a) {
        if (d[a] > 0.5) gap = std::min(gap, hi[a] - end[a]);
        if (d[a] < -0.5) gap = std::min(gap, end[a] - lo[a]);
      }
      return gap;
    };
    const double gapFrom = sideGap(from, -1.0), gapTo = sideGap(to, 1.0);
    if (std::min(gapFrom, gapTo) > kCornerSlackM) continue;
    const Eigen::Vector2d towardCorner = gapTo < gapFrom ? along : Eigen::Vector2d(-along);
    const Eigen::Vector2d corner =
        gapTo < gapFrom ? Eigen::Vector2d(to + gapTo * along) : Eigen::Vector2d(from - gapFrom * along);
    for (double d : distances) {
      for (double ratio : sideRatios) {
        const Eigen::Vector2d q = corner + d * inward - ratio * d * towardCorner;
        const Eigen::Vector2d stand = q + kStandBackM * inward;
        if (!free(q) || !free(stand) || !free(0.5 * (q + stand))) continue;
        for (double yawOffset : yawOffsets) {
          const double yaw = yawOf(std::cos(yawOffset) * -inward + std::sin(yawOffset) * towardCorner);
          for (double pitch : pitches) {
            const double pan = p.panAlongM;
            const std::vector<CameraState> views{
                state(q, yaw, pitch), state(q - pan * towardCorner, yaw - kPanYawRad, pitch - kPanPitchRad),
                state(q + pan * towardCorner - kPanTowardM * inward, yaw + kPanYawRad, pitch + kPanPitchRad)};
            double worstStd = 0.0, constraint = 1e9;
            bool ok = true;
            for (const CameraState& v : views) {
              const ViewMetrics m = measureView(renderer, poseOf(v));
              worstStd = std::max(worstStd, m.maxWindowStdM);
              ok = ok && m.validFraction >= kMinValid && worstStd < kMaxWindowStdM;
              if (!ok) break;
              constraint = std::min(constraint, m.minConstraint);
            }
            if (!ok || constraint <= best.constraint) continue;
            best = {views[0], {views[1], views[2]}, state(stand, yaw, pitch), inward, worstStd, constraint};
          }
        }
      }
    }
  }
  if (best.constraint < 0)
    throw Error(
        "synth: --stress blank-wall found no view of a blank corner in scene '" + scene.name + "' (seed " +
        std::to_string(scene.seed) +
        ") whose detector windows are flat and whose camera stands clear of the furniture; try another seed");
  return best;
}

StressTrajectory blankWallTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  if (scene.blankWalls.empty())
    throw Error("synth: --stress blank-wall needs a generated room with blank walls (scene '" + scene.name +
                "' has none)");
  constexpr double kMinSideTurnRad = 1.05,
                   kMaxSideTurnRad = 1.75;  // furnished views: 60-100 degrees off the blank view
  constexpr int kSideCandidates = 5;        // directions tried per side
  constexpr int kProbeScale = 8;            // candidate views are rendered at 1/8 resolution
  constexpr double kFurnishedPitchRad = kLevelPitchRad + 0.05;
  constexpr double kTurnPeakRadps = 0.8;  // turns peak at 46 deg/s (1.5 deg/frame)
  constexpr double kMinTurnS = 2.0;
  constexpr double kScanRad = 0.15;  // slow look-around in the furnished views, radians
  constexpr double kFurnishedS = 1.5, kWalkS = 2.0;
  const CornerView view = cornerView(scene, p);
  const double wallYaw = view.blank.yawRad;
  const Eigen::Vector3d stand = view.stand.position;
  // The furnished views: of the directions 60-100 degrees off the blank view, either way, the one with the
  // most depth structure (the one whose flattest detector window is least flat) among those that constrain
  // ICP well.
  const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
  double sideYaw = wallYaw + kMaxSideTurnRad, best = -2.0;
  for (int k = 0; k < kSideCandidates; ++k) {
    for (double side : {-1.0, 1.0}) {
      const double yaw = wallYaw + side * (kMinSideTurnRad +
                                           k * (kMaxSideTurnRad - kMinSideTurnRad) / (kSideCandidates - 1));
      const double structure = furnishedScore(renderer, poseOf({stand, yaw, kFurnishedPitchRad}));
      if (structure > best) best = structure, sideYaw = yaw;
    }
  }
  const double scan = (sideYaw > wallYaw ? 1.0 : -1.0) * kScanRad;  // further from the wall
  const double turnS = std::max(kMinTurnS, kMinJerkPeak * std::abs(sideYaw - wallYaw) / kTurnPeakRadps);
  // A little seeded variety in where the pan starts.
  const double jitter = rng.uniform(-0.02f, 0.02f);
  CameraState blank = view.blank;
  blank.position += jitter * Eigen::Vector3d(view.inward.x(), 0.0, view.inward.y());

  const CameraState start{stand, sideYaw + scan, kFurnishedPitchRad};
  const std::vector<Move> moves{
      {"furnished", kFurnishedS, {stand, sideYaw, kFurnishedPitchRad}},
      {"turn", turnS, view.stand},
      {"approach", kWalkS, blank},
      {"blank-wall", p.blankSeconds / 3, view.pan[0]},
      {"blank-wall", p.blankSeconds * 5 / 12, view.pan[1]},
      {"blank-wall", p.blankSeconds / 4, view.blank},
      {"retreat", kWalkS, view.stand},
      {"turn", turnS, {stand, sideYaw, kFurnishedPitchRad}},
      {"furnished", kFurnishedS, {stand, sideYaw + scan, kLevelPitchRad}},
  };
  return play(start, moves, p, rng);
}

}  // namespace

const std::vector<std::string>& stressNames() {
  static const std::vector<std::string> names{"bursts", "blank-wall"};
  return names;
}

StressKind parseStressKind(const std::string& name) {
  if (name == "bursts") return StressKind::Bursts;
  if (name == "blank-wall") return StressKind::BlankWall;
  throw Error("synth: unknown stress trajectory '" + name + "'; use one of: bursts, blank-wall");
}

StressTrajectory stressTrajectory(StressKind kind, const Scene& scene, uint64_t seed,
                                  const StressParams& params) {
  if (!scene.hasRoom)
    throw Error("synth: stress trajectories need a generated room (scene '" + scene.name + "' has none)");
  Rng rng(seed * 0x9E3779B97F4A7C15ull + (kind == StressKind::Bursts ? 0xB0257ull : 0xB1A4Cull));
  return kind == StressKind::Bursts ? burstsTrajectory(scene, params, rng)
                                    : blankWallTrajectory(scene, params, rng);
}

}  // namespace sb::synth
