// The rate limit of the bulky replies (issue 53 finding 8): a connection is sent the same MAP (or CLOUD) at
// most once per SocketServer::kSameBulkReplyInterval; asking again sooner gets ERROR with retry_after_s and
// the connection's further requests wait that long. Another connection, and a new grid, are served at once.
// Behaviour, not timing: which reply each request gets (the only wait checked is the hold's: nothing in
// 300 ms of a hold of about a second).

#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/daemon/server_harness.h"

using nlohmann::json;
using sb::test::LineClient;
using sb::test::ServerHarness;

namespace {

json readJson(LineClient& c) {
  const std::string line = c.readLine();
  INFO("line: " << line);
  REQUIRE_FALSE(line.empty());
  return json::parse(line);
}

// A 3 x 2 grid with three cloud cells, as the SLAM thread publishes one.
sb::daemon::MapReport grid(uint64_t frame) {
  sb::daemon::MapReport m;
  m.pass = 1;
  m.frame = frame;
  m.width = 3;
  m.height = 2;
  m.resolutionM = 0.05;
  m.up = "mount: test";
  m.cells = {100, 0, -1, 0, -1, 100};
  m.cloudResolutionM = 0.1;
  m.cloud = {{-3, 0, 2}, {0, 1, 5}, {4, -2, 0}};
  return m;
}

LineClient connect(ServerHarness& server) {
  LineClient c(server.path());
  REQUIRE(readJson(c)["class"] == "VERSION");
  return c;
}

void checkLimited(const json& reply, const std::string& request) {
  INFO(reply.dump());
  REQUIRE(reply["class"] == "ERROR");
  const std::string message = reply.value("message", "");
  CHECK(message.rfind(request + ": this connection was sent the same ", 0) == 0);
  CHECK(message.find("at most once every 1.0 s") != std::string::npos);
  CHECK(message.find("ask again in ") != std::string::npos);
  REQUIRE(reply.contains("retry_after_s"));
  CHECK(reply["retry_after_s"].get<double>() > 0.0);
  CHECK(reply["retry_after_s"].get<double>() <= 1.0);
}

}  // namespace

TEST_CASE("?MAP and ?CLOUD: the same reply once a second per connection, ERROR with retry_after_s sooner",
          "[daemon][socket]") {
  ServerHarness server;
  server.publishMap(grid(300));

  LineClient a = connect(server);
  a.send("?MAP;\n?MAP;\n?VERSION;\n");
  CHECK(readJson(a)["class"] == "MAP");
  checkLimited(readJson(a), "?MAP");
  // Held: the ?VERSION behind the refused ?MAP waits out the second.
  CHECK(a.readLine(300).empty());

  // Another connection is not limited by this one's requests; ?CLOUD has the same limit of its own.
  LineClient b = connect(server);
  b.send("?MAP;\n");
  CHECK(readJson(b)["class"] == "MAP");
  b.send("?CLOUD;\n?CLOUD;\n");
  CHECK(readJson(b)["class"] == "CLOUD");
  checkLimited(readJson(b), "?CLOUD");

  // A new grid is sent at once, however soon after the last.
  LineClient c = connect(server);
  c.send("?MAP;\n");
  CHECK(readJson(c)["frame"] == 300);
  server.publishMap(grid(301));
  c.send("?MAP;\n");
  CHECK(readJson(c)["frame"] == 301);

  // After the hold, a's waiting request is served (the daemon's tick or a POSE makes the loop turn; here a
  // frame nobody watches).
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  server.publishFrame(sb::test::scriptedFrame(1));
  CHECK(readJson(a)["class"] == "VERSION");
  a.send("?MAP;\n");
  const json again = readJson(a);
  CHECK(again["class"] == "MAP");
  CHECK(again["frame"] == 301);
}
