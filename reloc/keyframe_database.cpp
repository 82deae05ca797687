#include "reloc/keyframe_database.h"

#include <algorithm>

#include "core/error.h"

namespace sb {

KeyframeDatabase::KeyframeDatabase(size_t capacity, double minDissimilarity)
    : capacity_(capacity), minDissimilarity_(minDissimilarity) {
  if (capacity_ < 1) throw Error("KeyframeDatabase: capacity must be at least 1 keyframe");
  if (!(minDissimilarity_ >= 0.0 && minDissimilarity_ <= 1.0))
    throw Error("KeyframeDatabase: the harvesting dissimilarity must be in [0, 1]");
}

bool KeyframeDatabase::harvest(const FernCode& code, const Eigen::Isometry3d& T_camera_to_world, size_t frame) {
  if (!code.valid()) return false;
  constexpr double kSpacingMaxDeg = 30.0;
  bool unlike = true, far = maxSpacingM_ > 0.0;
  for (const Keyframe& k : keyframes_) {
    unlike = unlike && code.dissimilarity(k.code) > minDissimilarity_;
    if (far && (k.T_camera_to_world.translation() - T_camera_to_world.translation()).norm() <= maxSpacingM_ &&
        Eigen::AngleAxisd(k.T_camera_to_world.linear().transpose() * T_camera_to_world.linear()).angle() <=
            kSpacingMaxDeg * 3.14159265358979 / 180.0)
      far = false;
    if (!unlike && !far) return false;
  }
  if (keyframes_.size() == capacity_) keyframes_.pop_front();
  keyframes_.push_back({code, T_camera_to_world, frame});
  return true;
}

bool KeyframeDatabase::insert(const Keyframe& keyframe) {
  if (!keyframe.code.valid()) return false;
  if (!keyframes_.empty() && keyframes_.front().code.codes.size() != keyframe.code.codes.size()) return false;
  if (keyframes_.size() == capacity_) keyframes_.pop_front();
  keyframes_.push_back(keyframe);
  return true;
}

std::vector<const Keyframe*> KeyframeDatabase::all() const {
  std::vector<const Keyframe*> out;
  out.reserve(keyframes_.size());
  for (const Keyframe& k : keyframes_) out.push_back(&k);
  return out;
}

std::vector<KeyframeMatch> KeyframeDatabase::nearest(const FernCode& code, size_t k) const {
  std::vector<KeyframeMatch> all;
  if (!code.valid() || k == 0) return all;
  all.reserve(keyframes_.size());
  for (auto it = keyframes_.rbegin(); it != keyframes_.rend(); ++it) all.push_back({&*it, code.dissimilarity(it->code)});
  const size_t n = std::min(k, all.size());
  // Stable: among equally alike keyframes the newer (listed first) wins.
  std::stable_sort(all.begin(), all.end(),
                   [](const KeyframeMatch& a, const KeyframeMatch& b) { return a.dissimilarity < b.dissimilarity; });
  all.resize(n);
  return all;
}

size_t KeyframeDatabase::memoryBytes() const {
  size_t bytes = 0;
  for (const Keyframe& k : keyframes_) bytes += sizeof(Keyframe) + k.code.codes.capacity();
  return bytes;
}

}  // namespace sb
