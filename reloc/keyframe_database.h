#pragma once
// The relocaliser's memory of the map: keyframes (a fern code and the camera pose it was seen from), added
// while tracking is good when a view is unlike every stored one (Glocker et al. 2015's harvesting rule), and
// searched for the views most like a lost frame's. Bounded: at most `capacity` keyframes; when full, the
// oldest goes (with a map that follows the camera, the oldest views are the likeliest to have left it).
// Memory: capacity x (ferns bytes of code + a pose + bookkeeping), e.g. 300 x (500 + 72) bytes = 172 KB.
// Search compares a code with every stored one: capacity x ferns byte comparisons.

#include <Eigen/Geometry>
#include <cstddef>
#include <deque>
#include <vector>

#include "reloc/fern_encoder.h"

namespace sb {

struct Keyframe {
  FernCode code;
  Eigen::Isometry3d T_camera_to_world = Eigen::Isometry3d::Identity();  // volume frame, as the pipeline's poses
  size_t frame = 0;  // the run's frame it was taken from
};

struct KeyframeMatch {
  const Keyframe* keyframe = nullptr;  // valid until the database changes
  double dissimilarity = 1.0;          // FernCode::dissimilarity, [0, 1]
};

class KeyframeDatabase {
 public:
  // `capacity` >= 1 keyframes; a view becomes a keyframe when its dissimilarity to every stored one is above
  // `minDissimilarity` (in [0, 1]).
  KeyframeDatabase(size_t capacity, double minDissimilarity);

  // Adds the view as a keyframe when it is unlike every stored one (and its code is valid), or, with a spacing
  // set, when no keyframe was seen from within that spacing and 30 degrees of its pose (a map kept across runs,
  // runtime/map_store.h: a corridor's views are alike, and a restarted robot needs a keyframe near it). True
  // when added.
  bool harvest(const FernCode& code, const Eigen::Isometry3d& T_camera_to_world, size_t frame);
  // Up to `k` keyframes most like `code`, most alike first (ties: the newer first). Empty for an invalid code.
  std::vector<KeyframeMatch> nearest(const FernCode& code, size_t k) const;

  // Adds `keyframe` whatever it is like (a kept map's keyframes, runtime/map_store.h), the oldest going when
  // full. False for an invalid code or one of another size than the stored ones.
  bool insert(const Keyframe& keyframe);
  // Every keyframe, oldest first (valid until the database changes).
  std::vector<const Keyframe*> all() const;

  void setMaxSpacing(double metres) { maxSpacingM_ = metres; }  // 0: the dissimilarity rule alone

  size_t size() const { return keyframes_.size(); }
  size_t capacity() const { return capacity_; }
  // Bytes held by the keyframes (codes and poses), for the bound stated in docs/tracking-state.md and STATUS.
  size_t memoryBytes() const;

 private:
  size_t capacity_;
  double minDissimilarity_;
  double maxSpacingM_ = 0.0;
  std::deque<Keyframe> keyframes_;  // oldest first
};

}  // namespace sb
