#include "reloc/relocaliser.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/error.h"

namespace sb {

namespace {

constexpr double kDegPerRad = 57.29577951308232;

double rotationDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * kDegPerRad;
}

bool near(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double metres, double degrees) {
  return (a.translation() - b.translation()).norm() <= metres && rotationDeg(a, b) <= degrees;
}

// The better of two acceptable attempts: more of the pairs agreeing, then the smaller residual.
bool better(const TrackAttempt& a, const TrackAttempt& b) {
  const double ea = evidenceAgreement(a), eb = evidenceAgreement(b);
  if (ea != eb) return ea > eb;
  return a.residual < b.residual;
}

std::string describe(const TrackAttempt& a) {
  char buf[160];
  if (a.agreementInNoise)
    std::snprintf(buf, sizeof buf, "residual %.4f m, inliers %.2f, agreement %.2f (%.2f within the noise), conditioning %.2g",
                  a.residual, a.inlierFraction, a.pairAgreement, *a.agreementInNoise, a.quality.conditioning);
  else
    std::snprintf(buf, sizeof buf, "residual %.4f m, inliers %.2f, agreement %.2f, conditioning %.2g", a.residual,
                  a.inlierFraction, a.pairAgreement, a.quality.conditioning);
  return buf;
}

}  // namespace

RelocaliserParams::RelocaliserParams(const PipelineConfig& c)
    : candidates(c.relocaliseCandidates),
      confirmFrames(c.relocaliseConfirmFrames),
      minPairAgreement(c.relocaliseMinPairAgreement),
      agreementMargin(c.relocaliseAgreementMargin),
      minConditioning(c.relocaliseMinConditioning),
      maxMotionM(c.relocaliseMaxMotion),
      maxRotationDeg(c.relocaliseMaxRotationDeg),
      keyframeCapacity(static_cast<size_t>(c.keyframeCapacity)),
      keyframeMinDissimilarity(c.keyframeMinDissimilarity) {}

Relocaliser::Relocaliser(const RelocaliserParams& p)
    : params_(p), keyframes_(p.keyframeCapacity, p.keyframeMinDissimilarity) {
  if (p.candidates < 0 || p.confirmFrames < 1)
    throw Error("Relocaliser: candidates must be >= 0 and confirm frames >= 1");
}

size_t Relocaliser::seed(const std::vector<Keyframe>& keyframes) {
  size_t taken = 0;
  for (const Keyframe& k : keyframes) taken += keyframes_.insert(k) ? 1 : 0;
  return taken;
}

void Relocaliser::noteTracked(double pairAgreement) {
  if (!std::isfinite(pairAgreement) || params_.agreementWindowFrames == 0) return;
  tracked_.push_back(pairAgreement);
  while (tracked_.size() > params_.agreementWindowFrames) tracked_.pop_front();
}

double Relocaliser::requiredAgreement() const {
  constexpr size_t kMinKnown = 10;
  if (tracked_.size() < kMinKnown) return params_.minPairAgreement;
  std::vector<double> sorted(tracked_.begin(), tracked_.end());
  const auto p90 = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() * 9 / 10);
  std::nth_element(sorted.begin(), p90, sorted.end());
  return std::max(params_.minPairAgreement, *p90 - params_.agreementMargin);
}

bool Relocaliser::acceptable(const TrackAttempt& a, double minConditioning) const {
  return a.tracked && a.quality.known && a.quality.constrained && a.quality.conditioning >= minConditioning &&
         evidenceAgreement(a) >= requiredAgreement() &&
         a.T_camera_to_world.matrix().allFinite();
}

RelocaliseOutcome Relocaliser::relocalise(const FernCode& code, const Eigen::Isometry3d& heldPose,
                                          const TryPose& tryPose) {
  RelocaliseOutcome out;
  // Too little depth to recognise the place or to align anything (a covered lens, a blank view): nothing to
  // try, and a candidate being confirmed cannot hold on such a frame.
  if (!code.valid()) {
    reset();
    out.why = "too little depth to relocalise";
    return out;
  }
  // A candidate being confirmed: this frame, tracked from its last pose, must pass again and move little.
  if (pending_) {
    const TrackAttempt a = tryPose(*pending_);
    ++out.tries;
    if (acceptable(a, confirmConditioning_.value_or(params_.minConditioning)) &&
        near(a.T_camera_to_world, *pending_, params_.maxMotionM, params_.maxRotationDeg)) {
      pending_ = a.T_camera_to_world;
      out.confirmed = ++confirmed_;
      out.attempt = a;
      out.accepted = confirmed_ >= params_.confirmFrames;
      out.why = (out.accepted ? "relocalised: held " : "candidate held ") + std::to_string(confirmed_) + " of " +
                std::to_string(params_.confirmFrames) + " frames (" + describe(a) + ")";
      if (out.accepted) reset();
      return out;
    }
    out.why = "candidate lost (" + describe(a) + "); ";
    reset();
  }
  // Fresh candidates: the last good pose, then the keyframes most like this view (distinct poses only).
  std::vector<Eigen::Isometry3d> starts;
  if (tryHeldPose_) starts.push_back(heldPose);
  for (const KeyframeMatch& m : keyframes_.nearest(code, static_cast<size_t>(params_.candidates))) {
    std::vector<Eigen::Isometry3d> poses{m.keyframe->T_camera_to_world};
    for (double d : viewOffsetsM_) {
      Eigen::Isometry3d moved = m.keyframe->T_camera_to_world;
      moved.translation() += d * moved.linear().col(2);
      poses.push_back(moved);
    }
    for (const Eigen::Isometry3d& pose : poses) {
      bool seen = false;
      for (const auto& s : starts) seen = seen || near(s, pose, 0.01, 1.0);
      if (!seen) starts.push_back(pose);
    }
  }
  if (rotateStarts_ && starts.size() > 1)
    std::rotate(starts.begin(), starts.begin() + std::ptrdiff_t(freshSearches_++ % starts.size()), starts.end());
  std::optional<TrackAttempt> best;
  double bestAgreement = 0.0;  // of the tracked attempts, for the log
  for (const auto& start : starts) {
    const TrackAttempt a = tryPose(start);
    ++out.tries;
    if (a.tracked) bestAgreement = std::max(bestAgreement, evidenceAgreement(a));
    if (acceptable(a) && (!best || better(a, *best))) best = a;
  }
  if (!best) {
    char bar[96];
    std::snprintf(bar, sizeof bar, " (best agreement %.2f, needed %.2f)", bestAgreement, requiredAgreement());
    out.why += "no candidate of " + std::to_string(starts.size()) + " passed" + bar;
    return out;
  }
  pending_ = best->T_camera_to_world;
  confirmed_ = 1;
  out.confirmed = 1;
  out.attempt = best;
  out.accepted = params_.confirmFrames <= 1;
  out.why += (out.accepted ? "relocalised: " : "candidate found: ") + describe(*best);
  if (out.accepted) reset();
  return out;
}

}  // namespace sb
