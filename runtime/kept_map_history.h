#pragma once
// The path a restarted robot drove while it localises in a kept map (issue 55; docs/map-store.md), for the check
// that a relocaliser's candidate is the place the robot is in and not one that looks like it.
//
// A corridor's end wall looks alike in every building, and the wheels move a candidate there as they move the
// robot in any of them: the view in hand and the wheels say where along *a* corridor the camera is, not in which
// building. What tells the building is what the robot saw on its way: its earlier views, put where the wheels say
// they were taken relative to the candidate, must fit the kept surface wherever the kept surface covers them.
// The history keeps those views (one every kSpacingM of the wheels' path, the last kMaxViews) with the wheels'
// poses between them; `check` tracks each from its pose under the candidate against the kept surface (one ICP a
// view, its pairs counted within the depth sensor's noise, pipeline/pair_noise.h) and refuses the candidate when a
// view the kept surface covers does not fit there:
//   - covered: the kept surface pairs with at least kCoveredShare of the view's pixels (a view of what the store
//     never saw, or beyond the volume placed for the candidate, says nothing);
//   - fits: at least `minAgreement` of its pairs agree within the noise, and ICP, when it tracks the view, moves it
//     at most the wheels' error over the path back to it: kPlaceM plus three sigmas (noise_per_m a metre).
// Without wheels there is no path: a break in the wheels' steps starts the history again.

#include <Eigen/Geometry>
#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <string>

#include "drivers/frame_source.h"
#include "pipeline/pipeline.h"

namespace sb {

// One ICP of an earlier view from a pose against the kept surface (Pipeline::trackOtherFrom, bound).
using TryView = std::function<TrackAttempt(const DepthFrame& view, const Eigen::Isometry3d& start)>;

struct PathTest {
  double minAgreement = 0.0;  // of a covered view's pairs, within the sensor's noise
  double noisePerM = 0.0;     // the wheels' error (one sigma) per metre of path
};

struct PathVerdict {
  int views = 0;      // earlier views tried
  int covered = 0;    // of them, covered by the kept surface
  int fit = 0;        // of those, fitting in place
  double worstAgreement = 1.0;  // of the covered views (1 when none)
  double pathM = 0.0;           // the wheels' path back to the oldest covered view
  bool refused() const { return fit < covered; }
  std::string why;    // the covered views that did not fit (metres back, agreement, ICP's move), or a summary
};

class KeptMapHistory {
 public:
  // The frame in hand and the wheels' step to it from the frame before (camera frame; none: the path is broken
  // and the history starts again from this frame).
  void add(const DepthFrame& frame, const std::optional<Eigen::Isometry3d>& step);
  // The earlier views tried under `candidate` (the camera's pose now, in the kept map's frame): see above.
  PathVerdict check(const Eigen::Isometry3d& candidate, const PathTest& test, const TryView& tryView) const;
  void clear();
  size_t size() const { return views_.size(); }
  double pathM() const { return pathM_; }

  static constexpr double kSpacingM = 0.2;     // of the wheels' path between two views kept
  static constexpr size_t kMaxViews = 16;      // the last 3 m or so: ICP runs a decision, at most
  static constexpr double kCoveredShare = 0.5;  // of a view's pixels paired with the kept surface: most
  static constexpr double kPlaceM = 0.05;       // the candidate's own error: as the wheels' check of it
  static constexpr double kSigmas = 3.0;

 private:
  struct View {
    DepthFrame frame;
    Eigen::Isometry3d wheels;  // the camera's pose in the wheels' chain when it was taken
    double pathM = 0.0;        // the wheels' path up to it
  };
  std::deque<View> views_;
  Eigen::Isometry3d now_ = Eigen::Isometry3d::Identity();  // the camera now, in the same chain
  double pathM_ = 0.0;
  bool started_ = false;
};

}  // namespace sb
