// The daemon's typed config: defaults, the documented default file, and one clear error per bad value.

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/config_reader.h"
#include "core/error.h"
#include "daemon/daemon_config.h"
#include "daemon/slam_worker.h"
#include "tests/support/test_data.h"

using namespace sb::daemon;
using nlohmann::json;

namespace {

std::string errorOf(const json& j) {
  try {
    parseDaemonConfig(j, "test.json");
  } catch (const sb::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("daemon config: defaults and a full round trip", "[daemon][config]") {
  const DaemonConfig d = parseDaemonConfig(json::object());
  CHECK(d.socket.path == "/run/slambooster/slambooster.sock");
  CHECK(d.socket.mode == 0660);
  CHECK(d.source.pacing == "recorded");
  CHECK(d.slam.cpus == "auto");
  const json j = daemonConfigToJson(d);
  CHECK(daemonConfigToJson(parseDaemonConfig(j)) == j);
}

TEST_CASE("the documented default config equals the built-in defaults", "[daemon][config]") {
  const json file = sb::readJsonConfig(SB_DAEMON_DEFAULT_CONFIG, "config file");
  CHECK(file == daemonConfigToJson(DaemonConfig{}));
}

TEST_CASE("daemon config: values are read", "[daemon][config]") {
  const DaemonConfig c = parseDaemonConfig(json::parse(R"({
    "source": {"path": "/data/seq", "pacing": "fast", "at_end": "loop", "queue_frames": 2},
    "slam": {"cpus": "4-7", "controller": "slambooster"},
    "socket": {"mode": "0600", "control_group": "video", "client_buffer_kib": 64},
    "output": {"dir": "/tmp/x", "mesh": true}})"));
  CHECK(c.source.path == "/data/seq");
  CHECK(c.source.pacing == "fast");
  CHECK(c.source.atEnd == "loop");
  CHECK(c.source.queueFrames == 2);
  CHECK(c.slam.cpus == "4-7");
  CHECK(c.socket.mode == 0600);
  CHECK(c.socket.clientBufferBytes == 64 * 1024);
  CHECK(c.output.mesh);
}

TEST_CASE("daemon config: errors name the key, the value and what is allowed", "[daemon][config]") {
  using Catch::Matchers::Contains;
  CHECK_THAT(errorOf({{"sokcet", json::object()}}), Contains("unknown key 'sokcet'") && Contains("socket"));
  CHECK_THAT(errorOf({{"socket", {{"max_clients", 0}}}}),
             Contains("test.json: 'socket.max_clients' = 0") && Contains("[1, 4096]"));
  CHECK_THAT(errorOf({{"socket", {{"max_clients", "8"}}}}),
             Contains("'socket.max_clients' = \"8\"") && Contains("integer"));
  CHECK_THAT(errorOf({{"socket", {{"mode", "999"}}}}), Contains("'socket.mode' = \"999\"") && Contains("octal"));
  CHECK_THAT(errorOf({{"socket", {{"mode", 660}}}}), Contains("'socket.mode' = 660") && Contains("string"));
  CHECK_THAT(errorOf({{"source", {{"pacing", "slow"}}}}),
             Contains("'source.pacing' = \"slow\"") && Contains("\"recorded\", \"fast\""));
  CHECK_THAT(errorOf({{"source", {{"type", "kinect"}}}}),
             Contains("'source.type' = \"kinect\"") && Contains("\"replay\""));
  CHECK_THAT(errorOf({{"source", {{"speed", -1}}}}), Contains("'source.speed' = -1"));
  // Issue 33: a depth scale must be plausible (0 = from the sequence).
  CHECK_THAT(errorOf({{"source", {{"depth_scale", 0.5}}}}),
             Contains("'source.depth_scale' = 0.5") && Contains("100 to 100000"));
  CHECK_THAT(errorOf({{"source", {{"depth_scale", 1e6}}}}), Contains("'source.depth_scale'"));
  CHECK_THAT(errorOf({{"slam", {{"cpus", "7-4"}}}}), Contains("'slam.cpus' = \"7-4\"") && Contains("'7-4'"));
  CHECK_THAT(errorOf({{"slam", {{"threads", 1.5}}}}), Contains("'slam.threads' = 1.5"));
  CHECK_THAT(errorOf({{"output", {{"dir", ""}}}}), Contains("'output.dir' = \"\""));
  CHECK_THAT(errorOf({{"socket", {{"path", std::string(120, 'a')}}}}), Contains("'socket.path'") && Contains("107"));
  CHECK_THAT(errorOf({{"log_level", "loud"}}), Contains("'log_level' = \"loud\""));
  CHECK_THAT(errorOf(json::array()), Contains("must be a JSON object"));
  CHECK_THAT(errorOf({{"source", 3}}), Contains("'source' = 3"));
}

TEST_CASE("daemon config: command-line overrides", "[daemon][config]") {
  json j = json::object();
  applyOverride(j, "source.pacing=fast");
  applyOverride(j, "socket.max_clients=8");
  applyOverride(j, "output.mesh=true");
  applyOverride(j, "source.path=/a b/c");
  const DaemonConfig c = parseDaemonConfig(j);
  CHECK(c.source.pacing == "fast");
  CHECK(c.socket.maxClients == 8);
  CHECK(c.output.mesh);
  CHECK(c.source.path == "/a b/c");
  CHECK_THROWS_AS(applyOverride(j, "novalue"), sb::Error);
  CHECK_THROWS_AS(applyOverride(j, "a..b=1"), sb::Error);
  applyOverride(j, "socket.max_clients=\"8\"");
  CHECK_THROWS_AS(parseDaemonConfig(j), sb::Error);  // a quoted number stays a string: refused by type
}

TEST_CASE("daemon config: an override never replaces a config that is not an object", "[daemon][config]") {
  // Issue 23: [1,2], "hello" or {"source":5} with --pacing fast used to become a valid config.
  using Catch::Matchers::Contains;
  for (const json& file : {json::array({1, 2}), json("hello"), json(5)}) {
    json j = file;
    CHECK_THROWS_WITH(applyOverride(j, "source.pacing=fast"),
                      Contains("the configuration is") && Contains("not a JSON object"));
  }
  json j = {{"source", 5}};
  CHECK_THROWS_WITH(applyOverride(j, "source.pacing=fast"), Contains("'source' is 5, not a JSON object"));
  j = {{"source", {{"camera", "x"}}}};
  CHECK_THROWS_WITH(applyOverride(j, "source.camera.fx=1"), Contains("'source.camera' is \"x\""));
  j = json::object();
  applyOverride(j, "source.camera.fx=1");  // absent sections are still created
  CHECK(j["source"]["camera"]["fx"] == 1);
}

TEST_CASE("daemon config: deep nesting in a value or a file is an error, not a crash", "[daemon][config]") {
  using Catch::Matchers::Contains;
  // Issue 23: a 70000-deep config crashed the daemon (SIGSEGV) at start and on SIGHUP.
  json j = json::object();
  applyOverride(j, "source.path=" + std::string(70000, '['));  // not JSON within the bound: a plain string
  CHECK(j["source"]["path"].is_string());
  const std::string dir = sb::test::scratchDir("daemon_config_deep");
  std::ofstream(dir + "/deep.json") << std::string(70000, '[');
  CHECK_THROWS_WITH(sb::readJsonConfig(dir + "/deep.json", "config file"),
                    Contains("deep.json") && Contains("deeper than"));
  CHECK_THROWS_WITH(sb::readJsonConfig(dir, "config file"), Contains("is a directory"));
  // Deep but within the bound: the error quotes the value flat.
  CHECK_THAT(errorOf({{"source", {{"path", json::parse(std::string(60, '[') + std::string(60, ']'))}}}}),
             Contains("'source.path' = an array of 1 elements"));
}

TEST_CASE("daemon config: output rotation, its limits in bytes and when it applies", "[daemon][config]") {
  const DaemonConfig d = parseDaemonConfig(json::object());
  CHECK(d.output.rotation.mode == "live");
  CHECK(rotates(d.output.rotation, true));
  CHECK_FALSE(rotates(d.output.rotation, false));  // replays keep single files unless asked
  const sb::RetentionLimits l = retentionLimits(d.output.rotation);
  CHECK(l.segmentBytes == 64ull << 20);
  CHECK(l.keepBytes == 4096ull << 20);
  CHECK(l.minFreeBytes == 512ull << 20);

  const DaemonConfig a = parseDaemonConfig(json{
      {"output",
       {{"rotation", {{"mode", "always"}, {"segment_mib", 0.25}, {"keep_mib", 2}, {"keep_segments", 5}}}}}});
  CHECK(rotates(a.output.rotation, false));
  CHECK(retentionLimits(a.output.rotation).segmentBytes == 256u * 1024u);
  CHECK(retentionLimits(a.output.rotation).keepSegments == 5);
  CHECK_FALSE(rotates(
      parseDaemonConfig(json{{"output", {{"rotation", {{"mode", "never"}}}}}}).output.rotation, true));

  CHECK_THAT(errorOf(json{{"output", {{"rotation", {{"segment_mib", 64}, {"keep_mib", 100}}}}}}),
             Catch::Contains("output.rotation.keep_mib") && Catch::Contains("8 x segment_mib"));
  CHECK_THAT(errorOf(json{{"output", {{"rotation", {{"mode", "sometimes"}}}}}}),
             Catch::Contains("output.rotation.mode") && Catch::Contains("always"));
}

TEST_CASE("daemon config: the map slabs' retention, output.rotation.keep_slabs_mib", "[daemon][config]") {
  CHECK(parseDaemonConfig(json::object()).output.rotation.keepSlabsMib == 1024.0);
  const auto keep = [](double mib) {
    return parseDaemonConfig(json{{"output", {{"rotation", {{"keep_slabs_mib", mib}}}}}})
        .output.rotation.keepSlabsMib;
  };
  CHECK(keep(0) == 0.0);  // no limit
  CHECK(keep(16) == 16.0);
  CHECK(keep(65536) == 65536.0);
  CHECK_THAT(errorOf(json{{"output", {{"rotation", {{"keep_slabs_mib", 8}}}}}}),
             Catch::Contains("output.rotation.keep_slabs_mib") && Catch::Contains("8") &&
                 Catch::Contains("at least 16 MiB"));
  CHECK_THAT(errorOf(json{{"output", {{"rotation", {{"keep_slabs_mib", -1}}}}}}),
             Catch::Contains("output.rotation.keep_slabs_mib") && Catch::Contains("-1"));
  CHECK_THAT(errorOf(json{{"output", {{"rotation", {{"keep_slabs_mib", "lots"}}}}}}),
             Catch::Contains("output.rotation.keep_slabs_mib"));
}

TEST_CASE("daemon config: the controller file takes the run's form or the bare settings, never pipeline keys",
          "[daemon][config]") {
  using Catch::Matchers::Contains;
  const std::string dir = sb::test::scratchDir("daemon_controller_file");
  SlamConfig slam;
  slam.controller = "accurate";
  const sb::ControllerContext context{};
  slam.controllerConfig = dir + "/wrapped.json";
  std::ofstream(slam.controllerConfig) << R"({"controller": {"name": "step"}})";
  CHECK(loadControllerSettings(slam, context).name == "step");  // the file's name wins
  slam.controllerConfig = dir + "/bare.json";
  std::ofstream(slam.controllerConfig) << R"({"step": {}})";
  CHECK(loadControllerSettings(slam, context).name == "accurate");  // slam.controller when it names none
  slam.controllerConfig = dir + "/mixed.json";
  std::ofstream(slam.controllerConfig) << R"({"controller": "step", "volume_resolution": 64})";
  CHECK_THROWS_WITH(loadControllerSettings(slam, context),
                    Contains("mixed.json") && Contains("volume_resolution") && Contains("slam.pipeline_config"));
  slam.pipelineConfig = dir + "/mixed.json";  // and the pipeline file has no controller section
  CHECK_THROWS_WITH(buildPipelineConfig(slam, sb::SequenceInfo{}), Contains("'controller' is not read here"));
}
