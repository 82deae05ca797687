#include "synth/stress_kidnap.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "synth/renderer.h"
#include "synth/stress_moves.h"
#include "synth/stress_views.h"
#include "synth/synth_sequence.h"

namespace sb::synth::stress {

namespace {

constexpr int kMappingMoves = 4;
constexpr int kProbeScale = 8;  // views are measured on renders at 1/8 resolution

// The mapping part: from a start near the built-in orbit's centre (free floor space in every generated
// room), the camera sweeps its view across the furnished south-east corner in four calm moves (~0.3 rad of
// yaw and ~0.13 m each: under 16 deg/s and 0.12 m/s), the sweep's direction seeded.
struct Mapping {
  CameraState start;
  std::vector<CameraState> keys;  // start, then each move's target
  std::vector<Move> moves;
};

Mapping mapping(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr double kBaseZ = -1.2, kBaseYawRad = 0.75 * kPi;
  constexpr double kStartYawOffsetRad = 0.55, kSweepRad = 0.27, kSweepJitterRad = 0.05;
  constexpr double kStartJitterM = 0.1, kStepM = 0.12, kForwardJitterM = 0.06, kPitchJitterRad = 0.05;
  const Eigen::Vector3d base(0.0, eyeY(scene), kBaseZ);
  const double dir = rng.chance(0.5) ? 1.0 : -1.0;
  Mapping m;
  m.start = {base + Eigen::Vector3d(rng.uniform(-kStartJitterM, kStartJitterM), 0.0,
                                    rng.uniform(-kStartJitterM, kStartJitterM)),
             kBaseYawRad - dir * kStartYawOffsetRad + rng.uniform(-0.05f, 0.05f), kLevelPitchRad};
  m.keys.push_back(m.start);
  CameraState s = m.start;
  for (int k = 0; k < kMappingMoves; ++k) {
    CameraState t = s;
    t.yawRad += dir * (kSweepRad + rng.uniform(0.f, static_cast<float>(kSweepJitterRad)));
    t.position += dir * kStepM * lateralOf(s.yawRad) +
                  static_cast<double>(rng.uniform(-kForwardJitterM, kForwardJitterM)) * forwardOf(s.yawRad);
    t.pitchDownRad = kLevelPitchRad + rng.uniform(-kPitchJitterRad, kPitchJitterRad);
    m.moves.push_back({"mapping", p.kidnapMappingS / kMappingMoves, t});
    m.keys.push_back(t);
    s = t;
  }
  return m;
}

// A little hand jitter around a key view, so that "close to one seen earlier" is not "equal to".
CameraState near(CameraState s, Rng& rng) {
  constexpr double kJitterM = 0.04, kJitterRad = 0.04;
  s.position += Eigen::Vector3d(rng.uniform(-kJitterM, kJitterM), 0.0, rng.uniform(-kJitterM, kJitterM));
  s.yawRad += rng.uniform(-kJitterRad, kJitterRad);
  return s;
}

}  // namespace

StressTrajectory kidnapTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  Mapping m = mapping(scene, p, rng);
  const double coveredS =
      rng.uniform(static_cast<float>(p.kidnapCoveredMinS), static_cast<float>(p.kidnapCoveredMaxS));
  // Shown the first or second mapping view again: 50-70 degrees and 0.35-0.55 m from where the cover went on.
  const size_t j = static_cast<size_t>(rng.index(2));
  std::vector<Move> moves = m.moves;
  moves.push_back({"covered", coveredS, near(m.keys[j], rng)});
  moves.push_back({"after", p.kidnapAfterS / 2, near(m.keys[j + 1], rng)});
  moves.push_back({"after", p.kidnapAfterS / 2, near(m.keys[j + 2], rng)});
  return play(m.start, moves, p, rng);
}

StressTrajectory kidnapUnseenTrajectory(const Scene& scene, const StressParams& p, Rng& rng) {
  constexpr double kGridM = 0.25, kFreeM = 0.4;
  constexpr int kYaws = 24;
  constexpr double kLookRad = 0.1, kLookPitchRad = 0.04, kLookM = 0.04;  // the after part's look-around
  constexpr double kMinValid = 0.85, kMinConstraint = 0.01;              // a view that would track
  // Candidates are checked with half the allowed seen fraction: hand sway moves the after views a little.
  constexpr double kCandidateShare = 0.5;
  const Mapping m = mapping(scene, p, rng);
  const Rng swayRng = rng;  // the same sway phases for the mapping probe and the final trajectory
  Rng probeRng = swayRng;
  const StressTrajectory mapped = play(m.start, m.moves, p, probeRng);
  const double coveredS =
      rng.uniform(static_cast<float>(p.kidnapCoveredMinS), static_cast<float>(p.kidnapCoveredMaxS));

  const Renderer renderer(scene, iclNuimIntrinsics().scaled(kProbeScale));
  SeenSurfaces seen(renderer);
  constexpr size_t kMappingStep = 3;
  for (size_t i = 0; i < mapped.poses.size(); i += kMappingStep) seen.add(mapped.poses[i].T_camera_to_world);

  const CameraState& last = m.keys.back();
  const double reach = p.kidnapCoveredSpeedMps * coveredS;
  std::vector<CameraState> candidates;
  for (double x = scene.roomMin.x(); x <= scene.roomMax.x(); x += kGridM)
    for (double z = scene.roomMin.z(); z <= scene.roomMax.z(); z += kGridM) {
      const Eigen::Vector3d q(x, eyeY(scene), z);
      const Eigen::Vector3f qf = q.cast<float>();
      if ((q - last.position).norm() > reach || !scene.insideRoom(qf, kFreeM) ||
          scene.objectContaining(qf, kFreeM) >= 0)
        continue;
      for (int k = 0; k < kYaws; ++k) candidates.push_back({q, k * kTwoPi / kYaws, kLevelPitchRad});
    }
  for (size_t i = candidates.size(); i > 1; --i)
    std::swap(candidates[i - 1], candidates[static_cast<size_t>(rng.index(static_cast<int>(i)))]);

  for (const CameraState& c : candidates) {
    const CameraState left{c.position - kLookM * lateralOf(c.yawRad), c.yawRad - kLookRad,
                           c.pitchDownRad + kLookPitchRad};
    const CameraState right{c.position + kLookM * lateralOf(c.yawRad), c.yawRad + kLookRad,
                            c.pitchDownRad - kLookPitchRad};
    bool ok = true;
    for (const CameraState& v : {c, left, right}) {
      const ViewMetrics vm = measureView(renderer, poseOf(v));
      ok = vm.validFraction >= kMinValid && vm.minConstraint >= kMinConstraint &&
           seen.seenFraction(poseOf(v)) <= kCandidateShare * p.kidnapMaxSeenFraction;
      if (!ok) break;
    }
    if (!ok) continue;
    // The turn while covered goes the short way round.
    CameraState shown = c;
    shown.yawRad = last.yawRad + std::remainder(c.yawRad - last.yawRad, kTwoPi);
    const double turn = shown.yawRad - c.yawRad;
    std::vector<Move> moves = m.moves;
    moves.push_back({"covered", coveredS, shown});
    moves.push_back({"after", p.kidnapAfterS / 3, {left.position, left.yawRad + turn, left.pitchDownRad}});
    moves.push_back({"after", p.kidnapAfterS / 3, {right.position, right.yawRad + turn, right.pitchDownRad}});
    moves.push_back({"after", p.kidnapAfterS / 3, shown});
    Rng finalSway = swayRng;
    return play(m.start, moves, p, finalSway);
  }
  throw Error("synth: --stress kidnap-unseen found no view within " + std::to_string(reach) +
              " m of the mapping's end in scene '" + scene.name + "' (seed " + std::to_string(scene.seed) +
              ") that no mapping frame saw; try another seed");
}

}  // namespace sb::synth::stress
