// The bridge's reading of POSE/KNOBS/ENERGY and the covariance it derives from the tracking state (no ROS
// master needed).

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "ros/daemon_reports.h"
#include "ros/pose_covariance.h"

namespace {

using namespace sb::ros_bridge;

nlohmann::json pose() {
  return nlohmann::json::parse(R"({"class":"POSE","frame":41,"timestamp":1305031104.175,
    "position":[2.51,2.47,1.62],"quaternion":[0,0,0,1],"tracked":true,"corrected":false,"velocity":0.0043,
    "constrained":true,"conditioning":0.031,"weakest_motion":"tx","future_member":[1,2]})");
}

TEST_CASE("POSE: the state member wins; without it the state comes from tracked/constrained", "[ros]") {
  auto j = pose();
  CHECK(parsePose(j).state == TrackingState::good);
  j["state"] = "relocalised";
  CHECK(parsePose(j).state == TrackingState::relocalised);
  j["state"] = "weak";
  CHECK(parsePose(j).state == TrackingState::weak);
  j["state"] = "something new";  // a state this bridge does not know must not look certain
  CHECK(parsePose(j).state == TrackingState::lost);
  j.erase("state");
  j["constrained"] = false;
  CHECK(parsePose(j).state == TrackingState::weak);
  j["tracked"] = false;
  CHECK(parsePose(j).state == TrackingState::lost);
  auto old = pose();  // protocol 1.0: no quality members at all
  old.erase("constrained");
  old.erase("conditioning");
  old.erase("weakest_motion");
  const auto p = parsePose(old);
  CHECK(p.state == TrackingState::good);
  CHECK(p.frame == 41);
  CHECK(p.position[2] == 1.62);
}

TEST_CASE("reports with a missing or mistyped member are refused, naming it", "[ros]") {
  auto j = pose();
  j.erase("position");
  CHECK_THROWS_WITH(parsePose(j), Catch::Contains("position"));
  j = pose();
  j["tracked"] = "yes";
  CHECK_THROWS_WITH(parsePose(j), Catch::Contains("tracked"));
  const auto knobs = nlohmann::json::parse(
      R"({"class":"KNOBS","frame":41,"controller":"fixed","csr":2,"icp":1e-4,"pd":[6,5,4],"tr":1,"ir":1,"computation_ms":18.4})");
  const auto k = parseKnobs(knobs);
  CHECK(k.knobs.pyramidIterations[0] == 6);
  CHECK(k.computationMs == 18.4);
  const auto e = parseEnergy(nlohmann::json::parse(R"({"class":"ENERGY","frame":39,"joules":0.182,"mean_w":6.1})"));
  CHECK(e.joules == 0.182);
  CHECK_THROWS_WITH(parseEnergy(nlohmann::json::parse(R"({"class":"ENERGY","frame":-1,"joules":1})")),
                    Catch::Contains("frame"));
}

TEST_CASE("the covariance says what the state says, in the parent frame", "[ros]") {
  const CovarianceConfig c;
  PoseReport p = parsePose(pose());
  const auto good = poseCovariance(p, c);
  CHECK(good[0] == Approx(1e-4));
  CHECK(good[35] == Approx(1e-4));

  p.state = TrackingState::lost;
  const auto lost = poseCovariance(p, c);
  CHECK(lost[0] == Approx(1e6));
  CHECK(lost[14] == Approx(1e6));

  // Weak along the camera's z (forward); the camera is turned 90 degrees about the world's y axis, so its z
  // points along the world's -x: the uncertainty must be on the world's x, not z.
  p.state = TrackingState::weak;
  p.weakestMotion = "tz";
  const double h = std::sqrt(0.5);
  p.quaternion = {0, -h, 0, h};
  const auto weak = poseCovariance(p, c);
  CHECK(weak[0] == Approx(1.0));          // x x
  CHECK(weak[7] == Approx(1e-4));         // y y
  CHECK(weak[14] == Approx(1e-4).margin(1e-12));  // z z
  CHECK(std::abs(weak[2]) < 1e-9);        // no x-z coupling for an exact 90 degree turn
  // Without a named axis every axis is weak.
  p.weakestMotion.clear();
  const auto allWeak = poseCovariance(p, c);
  for (int i = 0; i < 6; ++i) CHECK(allWeak[static_cast<size_t>(i * 7)] == Approx(1.0));
}

}  // namespace
