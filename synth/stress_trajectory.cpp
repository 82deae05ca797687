#include "synth/stress_trajectory.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/rng.h"
#include "synth/stress_corridor.h"
#include "synth/stress_drive.h"
#include "synth/stress_kidnap.h"
#include "synth/stress_motions.h"
#include "synth/stress_moves.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"

namespace sb::synth {

namespace {

using namespace stress;  // CameraState, Move, play, ... (stress_moves.h)

double signTowards(double offset, Rng& rng) {
  if (std::abs(offset) > 1e-9) return offset > 0 ? -1.0 : 1.0;
  return rng.chance(0.5) ? 1.0 : -1.0;
}

StressTrajectory burstsTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr int kBursts = 4;
  constexpr double kCalmDriftM = 0.08, kCalmDriftRad = 0.2, kCalmDriftPitchRad = 0.06;
  constexpr double kMaxOffsetM = 0.35, kMaxYawOffsetRad = 0.6;
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
  moves.push_back({"calm", p.burstFinalCalmS, last});
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
  static const std::vector<std::string> names{"bursts", "blank-wall", "hard-bursts",   "robot", "pan",
                                              "corridor", "kidnap",   "kidnap-unseen", "drive"};
  return names;
}

StressKind parseStressKind(const std::string& name) {
  const std::vector<std::string>& names = stressNames();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<StressKind>(it - names.begin());  // in StressKind's order
  std::string known;
  for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
  throw Error("synth: unknown stress trajectory '" + name + "'; use one of: " + known);
}

namespace {

// The seed of a stress kind's generator: each kind its own stream for the same --seed.
uint64_t stressSeed(StressKind kind, uint64_t seed) {
  constexpr uint64_t kSalts[] = {0xB0257ull,   0xB1A4Cull,   0x4A2DB0257ull, 0x20B07ull, 0x9A4ull,
                                 0xC022D02ull, 0x41D4A9ull, 0x41D4A9A0ull,  0xD21BEull};
  return seed * 0x9E3779B97F4A7C15ull + kSalts[static_cast<int>(kind)];
}

}  // namespace

stress::DrivePath drivePath(const Scene& scene, uint64_t seed, const StressParams& params) {
  Rng rng(stressSeed(StressKind::Drive, seed));
  return stress::DrivePath(scene, params, rng);
}

StressTrajectory stressTrajectory(StressKind kind, const Scene& scene, uint64_t seed,
                                  const StressParams& params) {
  if (!scene.hasRoom)
    throw Error("synth: stress trajectories need a generated room (scene '" + scene.name + "' has none)");
  Rng rng(stressSeed(kind, seed));
  switch (kind) {
    case StressKind::Bursts:
      return burstsTrajectory(scene, params, rng);
    case StressKind::BlankWall:
      return blankWallTrajectory(scene, params, rng);
    case StressKind::HardBursts: {
      StressParams hard = params;
      hard.burstSpeedMps = params.hardBurstSpeedMps;
      hard.burstRateDegps = params.hardBurstRateDegps;
      hard.burstFinalCalmS = params.hardBurstFinalCalmS;
      return burstsTrajectory(scene, hard, rng);
    }
    case StressKind::Robot:
      return stress::robotTrajectory(scene, params, rng);
    case StressKind::Pan:
      return stress::panTrajectory(scene, params, rng);
    case StressKind::Corridor:
      return stress::corridorTrajectory(scene, params, rng);
    case StressKind::Kidnap:
      return stress::kidnapTrajectory(scene, params, rng);
    case StressKind::KidnapUnseen:
      return stress::kidnapUnseenTrajectory(scene, params, rng);
    case StressKind::Drive:
      return stress::driveTrajectory(scene, params, rng);
  }
  throw Error("synth: unknown stress kind " + std::to_string(static_cast<int>(kind)));
}

std::vector<std::pair<size_t, size_t>> coveredFrames(const StressTrajectory& trajectory) {
  std::vector<std::pair<size_t, size_t>> out;
  for (const StressSegment& s : trajectory.segments)
    if (s.label == kCoveredLabel) out.emplace_back(s.begin, s.end);
  return out;
}

Scene stressScene(StressKind kind, const Scene& scene, const StressParams& params) {
  return kind == StressKind::Corridor ? stress::corridorScene(scene, params) : scene;
}

}  // namespace sb::synth
