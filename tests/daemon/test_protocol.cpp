// The request parser and the message encoders of the socket protocol (docs/protocol.md).

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <vector>

#include "daemon/protocol.h"

using namespace sb::daemon;
using Catch::Matchers::Contains;

namespace {

std::string errorOf(std::string_view line) {
  const ParseResult r = parseRequest(line);
  REQUIRE_FALSE(r.request);
  REQUIRE_FALSE(r.error.empty());
  return r.error;
}

}  // namespace

TEST_CASE("requests parse", "[daemon][protocol]") {
  CHECK(parseRequest("?POLL;").request->command == Command::poll);
  CHECK(parseRequest("?POLL").request->command == Command::poll);
  CHECK(parseRequest("?STATUS;\r").request->command == Command::status);
  CHECK(parseRequest("?VERSION;").request->command == Command::version);
  const auto w = parseRequest(R"(?WATCH={"enable":true,"knobs":false,"future":1};)").request;
  REQUIRE(w);
  CHECK(w->command == Command::watch);
  CHECK(*w->watch.enable);
  CHECK_FALSE(*w->watch.knobs);
  CHECK_FALSE(w->watch.pose);
  CHECK(parseRequest("?WATCH;").request->command == Command::watch);
  const auto c =
      parseRequest(R"(?CONTROL={"controller":"slambooster","pin":{"csr":2,"pd0":6},"unpin":["ir"]})").request;
  REQUIRE(c);
  CHECK(*c->control.controller == "slambooster");
  CHECK(c->control.pin.at("csr") == 2);
  CHECK(c->control.pin.at("pd0") == 6);
  CHECK(c->control.unpin == std::vector<std::string>{"ir"});
  CHECK(parseRequest(R"(?CONTROL={"unpin":"all"})").request->control.unpin ==
        std::vector<std::string>{"all"});
}

TEST_CASE("malformed requests are refused with a reason", "[daemon][protocol]") {
  CHECK_THAT(errorOf(""), Contains("start with '?'"));
  CHECK_THAT(errorOf("WATCH;"), Contains("start with '?'"));
  CHECK_THAT(errorOf("?FLY;"), Contains("unknown request '?FLY'") && Contains("?WATCH"));
  CHECK_THAT(errorOf("?watch;"), Contains("unknown request"));
  CHECK_THAT(errorOf("?POLL={}"), Contains("?POLL must be followed by ';'"));
  CHECK_THAT(errorOf("?WATCH={"), Contains("one JSON object"));
  CHECK_THAT(errorOf("?WATCH=[1]"), Contains("one JSON object"));
  CHECK_THAT(errorOf("?WATCH={\"enable\":1}"), Contains("'enable' must be true or false"));
  CHECK_THAT(errorOf("?WATCH;;"), Contains("must be followed by"));
  CHECK_THAT(errorOf("?CONTROL;"), Contains("needs an argument object"));
  CHECK_THAT(errorOf("?CONTROL={}"), Contains("nothing to do"));
  CHECK_THAT(errorOf(R"(?CONTROL={"pin":{"speed":2}})"), Contains("unknown knob 'speed'") && Contains("csr"));
  CHECK_THAT(errorOf(R"(?CONTROL={"pin":{"csr":"2"}})"), Contains("must be a number"));
  CHECK_THAT(errorOf(R"(?CONTROL={"unpin":[3]})"), Contains("cannot unpin 3"));
  CHECK_THAT(errorOf(R"(?CONTROL={"controller":""})"), Contains("controller name"));
  CHECK_THAT(errorOf(std::string("?POLL;\0\xff", 8)), Contains("must be followed by ';'"));
  CHECK_THAT(errorOf("\x01\x02\xfe\xff"), Contains("start with '?'"));
}

TEST_CASE("every message carries its class; encodings are stable", "[daemon][protocol]") {
  // A frame's typed fields (daemon/frame_report.h makes them from the record; test_frame_report checks them
  // against frames.jsonl): POSE and KNOBS are written from them.
  FrameReport r;
  r.pose.frame = 7;
  r.pose.timestamp = 1.5;
  r.pose.position = {1.0, 2.0, 3.0};
  r.pose.tracked = true;
  r.pose.velocityMPerFrame = 0.01;
  r.knobs.frame = 7;
  r.knobs.controller = "fixed";
  r.knobs.knobs.integrationRate = 2;
  r.knobs.pinned = {"csr"};
  CHECK(toLine(poseMessage(r)) ==
        R"({"class":"POSE","constrained":true,"corrected":false,"frame":7,"odometry":false,"odometry_drift_m":0.0,)"
        R"("position":[1.0,2.0,3.0],"quaternion":[0.0,0.0,0.0,1.0],"state":"good","timestamp":1.5,"tracked":true,)"
        R"("velocity":0.01,"velocity_m_per_frame":0.01})"
        "\n");
  // Protocol 1.2: the tracking state; a lost frame says so (clients stop trusting the pose).
  FrameReport lost = r;
  lost.pose.tracked = false;
  lost.pose.state = sb::TrackingState::lost;
  CHECK(poseMessage(lost).at("state") == "lost");
  // Protocol 1.1: a frame whose geometry left a motion free says so, with the conditioning and the motion.
  FrameReport wall = r;
  wall.pose.constrained = false;
  wall.pose.conditioning = 0.0004;
  wall.pose.weakestMotion = "tx";
  const nlohmann::json pose = poseMessage(wall);
  CHECK(pose.at("constrained") == false);
  CHECK(pose.at("conditioning") == 0.0004);
  CHECK(pose.at("weakest_motion") == "tx");
  // Protocol 1.3: the frame log's name of the velocity beside the old one.
  CHECK(pose.at("velocity") == pose.at("velocity_m_per_frame"));
  // Protocol 1.4: the odometry state, whether the frame had odometry, the distance driven on it alone.
  CHECK(versionMessage("x").at("proto_minor") == 11);
  FrameReport wheels = r;
  wheels.pose.state = sb::TrackingState::odometry;
  wheels.pose.odometry = true;
  wheels.pose.odometryDriftM = 0.5;
  CHECK(poseMessage(wheels).at("state") == "odometry");
  CHECK(poseMessage(wheels).at("odometry_drift_m") == 0.5);
  CHECK(toLine(knobsMessage(r)) ==
        R"({"class":"KNOBS","computation_ms":0.0,"controller":"fixed","csr":1,"frame":7,"icp":1e-05,"ir":2,)"
        R"("pd":[10,5,4],"pinned":["csr"],"tr":1})"
        "\n");
  CHECK(versionMessage("0.1.0")["class"] == "VERSION");
  CHECK(energyMessage(sb::EnergyReport{})["class"] == "ENERGY");
  CHECK(statusMessage({{"fps", 1}})["class"] == "STATUS");
  CHECK(errorMessage("x")["class"] == "ERROR");
  CHECK(watchMessage(true, true, false, true)["class"] == "WATCH");
  // Invalid UTF-8 in a string never throws on the wire.
  CHECK(toLine(errorMessage("bad \xff byte")).find("ERROR") != std::string::npos);
}

TEST_CASE("deeply nested arguments are refused without recursion", "[daemon][protocol]") {
  // Issue 23: ?CONTROL={"unpin":[ + 100000 x [ crashed the daemon while its error dumped the value.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  CHECK_THAT(errorOf("?CONTROL={\"unpin\":" + deep + "}"), Contains("deeper than"));
  CHECK_THAT(errorOf("?CONTROL={\"unpin\":" + std::string(100000, '[')), Contains("deeper than"));
  CHECK_THAT(errorOf("?WATCH={\"x\":" + deep + "}"), Contains("deeper than"));
  // Within the bound the refusal quotes the value flat.
  CHECK_THAT(errorOf("?CONTROL={\"unpin\":[[[[1]]]]}"), Contains("cannot unpin an array of 1 elements"));
  CHECK(errorOf("?CONTROL={\"unpin\":[\"" + std::string(100000, 'x') + "\"]}").size() < 400);
  CHECK(errorOf("?CONTROL={\"pin\":{\"" + std::string(100000, 'x') + "\":1}}").size() < 400);
  // A control character in a long string: nlohmann's message quotes the whole token; the reply must not.
  CHECK(errorOf("?CONTROL={\"pin\":{\"" + std::string(100000, 'k') + "\x01\":1}}").size() < 400);
  // A reply quoting a 1 MiB controller name overflowed the client's buffer: the client got no answer.
  CHECK_THAT(errorOf("?CONTROL={\"controller\":\"" + std::string(100000, 'x') + "\"}"),
             Contains("1 to 64 bytes"));
}

TEST_CASE("CLOUD: a cloud over the bound is voxel-filtered, negative cells floored", "[daemon][protocol]") {
  MapReport m;
  m.cloudResolutionM = 0.1;
  for (int32_t x = 6; x >= -2; --x) m.cloud.push_back({x, 0, 0});  // 9 cells in a row, unsorted
  boundCloud(m, 9);  // within the bound: as it was, sorted
  CHECK(m.cloud.size() == 9);
  CHECK(m.cloudResolutionM == 0.1);
  CHECK(std::is_sorted(m.cloud.begin(), m.cloud.end()));
  boundCloud(m, 8);  // 0.2 m cells: -2 and -1 floor to -1, 0 and 1 to 0, ..., 6 to 3
  CHECK(m.cloud == std::vector<std::array<int32_t, 3>>{{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
  CHECK(m.cloudResolutionM == Approx(0.2));
  // The octants around the origin never merge: a bound below 8 is 8, and the filter ends.
  m.cloud.clear();
  for (int32_t x : {-1, 0})
    for (int32_t y : {-1, 0})
      for (int32_t z : {-1, 0}) m.cloud.push_back({x, y, z});
  m.cloud.push_back({1000, 1000, 1000});
  m.cloudResolutionM = 0.1;
  boundCloud(m, 1);
  CHECK(m.cloud.size() == 8);  // the far cell halved 10 times into {0, 0, 0}
  CHECK(m.cloudResolutionM == Approx(0.1 * 1024));
  CHECK(cloudMessage(m).dump().find(R"("cells":[-1,-1,-1,-1,-1,0,)") != std::string::npos);
}
