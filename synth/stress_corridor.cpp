#include "synth/stress_corridor.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "synth/renderer.h"
#include "synth/stress_moves.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"

namespace sb::synth::stress {

namespace {

constexpr double kClearDepthM = 1.75;  // furniture is removed this far into the room from the stretch
// While sliding, the view's edge keeps this far inside the stretch (hand sway and the pitched image corners
// reach ~7 cm further).
constexpr double kEdgeMarginM = 0.12;
constexpr double kMinEndM = 1.0;                  // the stretch ends this far from a corner at least
constexpr double kCandidateStepM = 0.2;           // spacing of the stretch positions tried along a wall
constexpr double kEndTurnRad = 40.0 * kDegToRad;  // turned this far towards an end, furniture comes in view
constexpr double kEndPitchRad = 0.35;             // and looking down at it
constexpr double kStandTurnRad = 50.0 * kDegToRad;
constexpr double kStandM = 2.3;     // the start, this far from the wall
constexpr double kOnPlaneM = 1e-3;  // a pixel sees the wall when its depth is the wall's to this
constexpr int kProbeScale = 8;      // candidate views are rendered at 1/8 resolution

// The cleared stretch: on the wall of scene.blankWalls[wall], `middle` is its middle (plan x, z).
struct Stretch {
  size_t wall = 0;
  Eigen::Vector2d middle, along, inward;  // metres; unit; unit into the room
  double score = -1.0;                    // the least ICP constraint (measureView) of the end views
};

// Where the wall of `w` runs, in metres along it from w.from: [first, second].
std::pair<double, double> wallExtent(const Scene& scene, const BlankWall& w) {
  const Eigen::Vector2d from = w.from.cast<double>(), along = (w.to - w.from).cast<double>().normalized();
  double lo = 1e9, hi = -1e9;
  for (double x : {scene.roomMin.x(), scene.roomMax.x()})
    for (double z : {scene.roomMin.z(), scene.roomMax.z()}) {
      const double u = along.dot(Eigen::Vector2d(x, z) - from);
      lo = std::min(lo, u), hi = std::max(hi, u);
    }
  return {lo, hi};
}

Scene cleared(const Scene& scene, const Stretch& s, double lengthM) {
  Scene out = scene;
  out.primitives.clear();
  for (const Primitive& prim : scene.primitives) {
    bool inFront = false;
    if (prim.bounded()) {
      double uLo = 1e9, uHi = -1e9, vLo = 1e9;
      for (const Eigen::Vector3f& c : prim.corners()) {
        const Eigen::Vector2d q = Eigen::Vector2d(c.x(), c.z()) - s.middle;
        uLo = std::min(uLo, s.along.dot(q)), uHi = std::max(uHi, s.along.dot(q));
        vLo = std::min(vLo, s.inward.dot(q));
      }
      inFront = uHi > -0.5 * lengthM && uLo < 0.5 * lengthM && vLo < kClearDepthM;
    }
    if (!inFront) out.primitives.push_back(prim);
  }
  BlankWall& w = out.blankWalls[s.wall];
  w.from = (s.middle - 0.5 * lengthM * s.along).cast<float>();
  w.to = (s.middle + 0.5 * lengthM * s.along).cast<float>();
  w.clearDepthM = static_cast<float>(kClearDepthM);
  return out;
}

// The camera's half view width on a wall `distanceM` away (pixel edges), metres.
double halfViewM(double distanceM) {
  const Intrinsics k = iclNuimIntrinsics();
  return distanceM * (k.cx + 0.5) / k.fx;
}

// Key views of a stretch: facing the wall or turned towards an end by `turnRad` at `u` metres along it
// from the middle, `distanceM` from the wall.
CameraState viewOf(const Scene& scene, const Stretch& s, double u, double distanceM, double turnRad,
                   double pitch) {
  const Eigen::Vector2d q = s.middle + u * s.along + distanceM * s.inward;
  const Eigen::Vector2d look = std::cos(turnRad) * -s.inward + std::sin(turnRad) * s.along;
  return {Eigen::Vector3d(q.x(), eyeY(scene), q.y()), yawOf(look), pitch};
}

Stretch findStretch(const Scene& scene, const StressParams& p) {
  constexpr double kMinValid = 0.9, kFreeM = 0.3;
  const double L = p.corridorStretchM, d = p.corridorDistanceM;
  const double slideEnd = 0.5 * L - halfViewM(d) - kEdgeMarginM;
  Stretch best;
  for (size_t wi = 0; wi < scene.blankWalls.size(); ++wi) {
    const BlankWall& w = scene.blankWalls[wi];
    const auto [lo, hi] = wallExtent(scene, w);
    const Eigen::Vector2d from = w.from.cast<double>(), along = (w.to - w.from).cast<double>().normalized();
    for (double u = lo + 0.5 * L + kMinEndM; u <= hi - 0.5 * L - kMinEndM + 1e-9; u += kCandidateStepM) {
      Stretch s{wi, from + u * along, along, w.inward.cast<double>()};
      const Scene room = cleared(scene, s, L);
      const Renderer renderer(room, iclNuimIntrinsics().scaled(kProbeScale));
      double score = 1e9;
      for (double end : {-1.0, 1.0}) {
        const CameraState at = viewOf(room, s, end * slideEnd, d, end * kEndTurnRad, kEndPitchRad);
        const CameraState stand =
            viewOf(room, s, end * slideEnd, kStandM, end * kStandTurnRad, kLevelPitchRad);
        for (const CameraState& v : {at, stand}) {
          const Eigen::Vector3f c = v.position.cast<float>();
          const ViewMetrics m = measureView(renderer, poseOf(v));
          if (!room.insideRoom(c, kFreeM) || room.objectContaining(c, kFreeM) >= 0 ||
              m.validFraction < kMinValid)
            score = -1.0;
          score = std::min(score, m.minConstraint);
        }
      }
      if (score > best.score) best = s, best.score = score;
    }
  }
  if (best.score <= 0.0)
    throw Error("synth: --stress corridor found no stretch of wall in scene '" + scene.name + "' (seed " +
                std::to_string(scene.seed) + ") with furniture in view beyond both ends; try another seed");
  return best;
}

// True when every pixel of the exact render sees the stretch's wall (and nothing else).
bool seesOnlyWall(const Renderer& renderer, const Eigen::Isometry3d& T_camera_to_world, const Stretch& s) {
  IdealFrame ideal;
  renderer.renderIdeal(T_camera_to_world, ideal);
  const Intrinsics& k = renderer.intrinsics();
  const Eigen::Vector3d n(s.inward.x(), 0.0, s.inward.y());
  const double c = n.dot(Eigen::Vector3d(s.middle.x(), 0.0, s.middle.y()));
  const Eigen::Vector3d o = T_camera_to_world.translation();
  const Eigen::Matrix3d R = T_camera_to_world.linear();
  for (int y = 0; y < k.height; ++y) {
    for (int x = 0; x < k.width; ++x) {
      const double z = ideal.depthM(x, y);
      const double denom = n.dot(R * Eigen::Vector3d((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0));
      if (z <= 0.0 || std::abs(denom) < 1e-9 || std::abs((c - n.dot(o)) / denom - z) > kOnPlaneM)
        return false;
    }
  }
  return true;
}

}  // namespace

Scene corridorScene(const Scene& scene, const StressParams& p) {
  return cleared(scene, findStretch(scene, p), p.corridorStretchM);
}

StressTrajectory corridorTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  if (scene.blankWalls.empty())
    throw Error("synth: --stress corridor needs a generated room (scene '" + scene.name + "' has none)");
  constexpr double kTurnS = 1.4, kHoldS = 0.6, kWalkS = 2.0, kStartS = 1.0;
  constexpr double kScanRad = 0.1;  // slow look-around at the start and while holding, radians
  const Stretch s = findStretch(scene, p);
  const Scene room = cleared(scene, s, p.corridorStretchM);
  const double d = p.corridorDistanceM, pitch = p.corridorPitchRad;
  const double slideEnd = 0.5 * p.corridorStretchM - halfViewM(d) - kEdgeMarginM;
  double end = rng.chance(0.5) ? 1.0 : -1.0;  // the end the camera is at
  const double jitter = rng.uniform(-0.02f, 0.02f);

  const CameraState start = viewOf(room, s, end * slideEnd, kStandM, end * kStandTurnRad, kLevelPitchRad);
  std::vector<Move> moves;
  CameraState last = start;
  auto add = [&](const char* label, double durationS, CameraState target) {
    target.yawRad = last.yawRad + std::remainder(target.yawRad - last.yawRad, kTwoPi);  // the short way round
    moves.push_back({label, durationS, target});
    last = target;
  };
  add("furnished", kStartS,
      viewOf(room, s, end * slideEnd, kStandM, end * (kStandTurnRad - kScanRad), kLevelPitchRad));
  add("approach", kWalkS, viewOf(room, s, end * slideEnd, d, end * kEndTurnRad, kEndPitchRad));
  for (int pass = 0; pass < p.corridorPasses; ++pass) {
    add("turn", kTurnS, viewOf(room, s, end * slideEnd, d + jitter, 0.0, pitch));
    end = -end;
    add("slide", p.corridorSlideS, viewOf(room, s, end * slideEnd, d - jitter, 0.0, pitch));
    add("turn", kTurnS, viewOf(room, s, end * slideEnd, d, end * kEndTurnRad, kEndPitchRad));
    add("furnished", kHoldS,
        viewOf(room, s, end * slideEnd, d, end * (kEndTurnRad + kScanRad), kEndPitchRad));
  }
  StressTrajectory out = play(start, moves, p, rng);

  // Label the frames that see the wall only, on a full-size exact render; merge the segments again.
  const Renderer renderer(room, iclNuimIntrinsics());
  std::vector<std::string> labels(out.poses.size());
  for (const StressSegment& seg : out.segments)
    for (size_t i = seg.begin; i < seg.end; ++i) {
      labels[i] = seg.label;
      if ((seg.label == "slide" || seg.label == "turn") &&
          seesOnlyWall(renderer, out.poses[i].T_camera_to_world, s))
        labels[i] = "wall-only";
      else if (seg.label == "slide")
        labels[i] = "furnished";
    }
  out.segments.clear();
  for (size_t i = 0; i < labels.size(); ++i) {
    if (out.segments.empty() || out.segments.back().label != labels[i])
      out.segments.push_back({labels[i], i, i});
    out.segments.back().end = i + 1;
  }
  return out;
}

}  // namespace sb::synth::stress
