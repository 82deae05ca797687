#include "synth/stress_trajectory.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "synth/builtin_trajectory.h"
#include "synth/renderer.h"
#include "synth/rng.h"
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
  constexpr double kSwingShare = 0.9, kFlickShare = 0.82;  // of the peak speed / rate, for combined bursts
  // The built-in orbit's centre: free floor space in every generated room; facing the south-east corner.
  const Eigen::Vector3d base(0.0, scene.roomMax.y() - kEyeHeightM, -1.2);
  const double baseYaw = 0.75 * kPi;
  const double burstShift = p.burstSpeedMps * p.burstDurationS / kMinJerkPeak;
  const double burstTurn = p.burstRateDegps * kPi / 180.0 * p.burstDurationS / kMinJerkPeak;

  enum Kind { Translate, Rotate, Swing, Tilt };
  std::vector<Kind> order{Translate, Rotate, Swing, Tilt};
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

    CameraState burst = calm;
    const Eigen::Vector3d lateral = lateralOf(calm.yawRad);
    const double sideShift = signTowards((calm.position - base).dot(lateral), rng);
    const double sideTurn = signTowards(calm.yawRad - baseYaw, rng);
    switch (order[static_cast<size_t>(b)]) {
      case Translate:
        burst.position += sideShift * burstShift * lateral;
        break;
      case Rotate:
        burst.yawRad += sideTurn * burstTurn;
        break;
      case Swing:  // a sideways step while turning the same way: the view sweeps fast
        burst.position += sideShift * kSwingShare * burstShift * lateral;
        burst.yawRad += sideShift * kFlickShare * burstTurn;
        break;
      case Tilt:
        burst.pitchDownRad += signTowards(calm.pitchDownRad - kLevelPitchRad, rng) * kFlickShare * burstTurn;
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

// How much depth structure a view has: the smallest, over the four image quadrants, std of the exact depth
// (metres) in a coarse render; -1 when under 85% of the pixels have a reading (out of sensor range).
double viewStructure(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world) {
  constexpr double kMinValid = 0.85;
  SensorModel exact;
  exact.noise = false;
  DepthMeters depth;
  renderer.render(T_camera_to_world, exact, 0, depth, /*parallel=*/false);
  const int w = depth.width(), h = depth.height();
  double smallest = 1e9;
  size_t valid = 0;
  for (int q = 0; q < 4; ++q) {
    double sum = 0, sumSq = 0;
    int n = 0;
    for (int y = q / 2 ? h / 2 : 0; y < (q / 2 ? h : h / 2); ++y)
      for (int x = q % 2 ? w / 2 : 0; x < (q % 2 ? w : w / 2); ++x)
        if (const double z = depth(x, y); z > 0) sum += z, sumSq += z * z, ++n;
    valid += static_cast<size_t>(n);
    smallest = n ? std::min(smallest, std::sqrt(std::max(0.0, sumSq / n - (sum / n) * (sum / n)))) : 0.0;
  }
  return static_cast<double>(valid) < kMinValid * w * h ? -1.0 : smallest;
}

StressTrajectory blankWallTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  if (scene.blankWalls.empty())
    throw Error("synth: --stress blank-wall needs a generated room with blank walls (scene '" + scene.name +
                "' has none)");
  constexpr double kStandOffM = 0.35;  // where the walk starts: this far into the camera space, metres
  constexpr double kMinSideTurnRad = 1.05,
                   kMaxSideTurnRad = 2.09;  // furnished views: 60-120 degrees off the wall
  constexpr int kSideCandidates = 5;        // directions tried per side
  constexpr int kProbeScale = 8;            // candidate views are rendered at 1/8 resolution
  constexpr double kFurnishedPitchRad = kLevelPitchRad + 0.05;
  constexpr double kTurnPeakRadps = 1.31;  // turns peak at 75 deg/s
  constexpr double kMinTurnS = 2.0;
  constexpr double kScanRad = 0.15;       // slow look-around in the furnished views, radians
  constexpr double kPanYawRad = 0.04;     // yaw during the pan, radians
  constexpr double kWallPitchRad = 0.05;  // nearly level while facing the wall
  constexpr double kFurnishedS = 1.5, kWalkS = 2.0;
  const BlankWall& wall =
      *std::max_element(scene.blankWalls.begin(), scene.blankWalls.end(),
                        [](const BlankWall& a, const BlankWall& b) { return a.clearDepthM < b.clearDepthM; });
  const Eigen::Vector2f along = (wall.to - wall.from).normalized();
  const Eigen::Vector2f mid = wall.middle() + along * rng.uniform(-0.05f, 0.05f);
  auto at = [&](float fromWallM, float alongM) {
    const Eigen::Vector2f q = mid + wall.inward * fromWallM + along * alongM;
    return Eigen::Vector3d(q.x(), scene.roomMax.y() - kEyeHeightM, q.y());
  };
  const double wallYaw = std::atan2(-wall.inward.x(), -wall.inward.y());
  const Eigen::Vector3d stand = at(wall.clearDepthM + static_cast<float>(kStandOffM), 0.f);
  // The furnished views: of the directions 60-120 degrees off the wall, either way, the one with the most
  // depth structure (the one whose flattest image quadrant is least flat).
  const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
  double sideYaw = wallYaw + kMaxSideTurnRad, best = -2.0;
  for (int k = 0; k < kSideCandidates; ++k) {
    for (double side : {-1.0, 1.0}) {
      const double yaw = wallYaw + side * (kMinSideTurnRad +
                                           k * (kMaxSideTurnRad - kMinSideTurnRad) / (kSideCandidates - 1));
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = handheldRotation(yaw, kFurnishedPitchRad, 0.0);
      T.translation() = stand;
      const double structure = viewStructure(renderer, T);
      if (structure > best) best = structure, sideYaw = yaw;
    }
  }
  const double scan = (sideYaw > wallYaw ? 1.0 : -1.0) * kScanRad;  // further from the wall
  const double turnS = std::max(kMinTurnS, kMinJerkPeak * std::abs(sideYaw - wallYaw) / kTurnPeakRadps);

  const float d = static_cast<float>(p.wallDistanceM), pan = static_cast<float>(p.panAlongM);
  const CameraState start{stand, sideYaw + scan, kFurnishedPitchRad};
  const std::vector<Move> moves{
      {"furnished", kFurnishedS, {stand, sideYaw, kFurnishedPitchRad}},
      {"turn", turnS, {stand, wallYaw, kWallPitchRad}},
      {"approach", kWalkS, {at(d, 0.f), wallYaw, kWallPitchRad}},
      {"blank-wall", p.blankSeconds / 3, {at(d, pan), wallYaw + kPanYawRad, kWallPitchRad}},
      {"blank-wall", p.blankSeconds * 5 / 12, {at(d, -pan), wallYaw - kPanYawRad, kWallPitchRad}},
      {"blank-wall", p.blankSeconds / 4, {at(d, 0.f), wallYaw, kWallPitchRad}},
      {"retreat", kWalkS, {stand, wallYaw, kWallPitchRad}},
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
