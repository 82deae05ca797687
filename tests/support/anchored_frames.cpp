#include "tests/support/anchored_frames.h"

#include <Eigen/Geometry>
#include <fstream>
#include <stdexcept>

namespace sb::test {

namespace {

// frames.jsonl's pose: "position" [x, y, z] and "quaternion" [x, y, z, w], camera to world.
Eigen::Isometry3d poseOf(const nlohmann::json& f) {
  const auto p = f.at("position"), q = f.at("quaternion");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(q[3].get<double>(), q[0].get<double>(), q[1].get<double>(),
                                     q[2].get<double>()).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  return pose;
}

}  // namespace

std::vector<AnchoredFrame> anchoredFrames(const std::string& run, const sb::Trajectory& truth) {
  const std::string path = run + "/frames.jsonl";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  std::vector<AnchoredFrame> frames;
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // the estimate's frame to the truth's
  size_t lineNo = 0;
  for (std::string text; std::getline(in, text);) {
    ++lineNo;
    AnchoredFrame a;
    a.line = nlohmann::json::parse(text);
    a.frame = a.line.at("frame").get<size_t>();
    if (a.frame >= truth.size())
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": frame " + std::to_string(a.frame) +
                               " has no pose in the truth (" + std::to_string(truth.size()) + " poses)");
    a.timestamp = a.line.at("timestamp").get<double>();
    a.state = a.line.at("state").get<std::string>();
    const Eigen::Isometry3d pose = poseOf(a.line);
    if (frames.empty()) anchor = truth[a.frame].T_camera_to_world * pose.inverse();
    a.error = (anchor * pose).translation() - truth[a.frame].position();
    a.errorM = a.error.norm();
    frames.push_back(std::move(a));
  }
  return frames;
}

}  // namespace sb::test
