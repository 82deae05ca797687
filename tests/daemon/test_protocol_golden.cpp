// Golden regression of the socket protocol: scripted requests in, expected JSON lines out (golden/*.script,
// format in golden/README.md), against the real socket server on a real Unix socket.

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "tests/daemon/server_harness.h"

namespace fs = std::filesystem;
using sb::test::LineClient;
using sb::test::ServerHarness;

namespace {

sb::daemon::MapReport handMadeGrid(uint64_t frame) {
  sb::daemon::MapReport m;
  m.pass = 1;
  m.frame = frame;
  m.width = 3;
  m.height = 2;
  m.resolutionM = 0.05;
  m.originX = -1.25;
  m.originY = 0.5;
  m.up = "mount: test";
  m.cells = {100, 0, -1, 0, -1, 100};
  return m;
}

// Expands \n \r \\ \xNN; a trailing \c means "no newline".
std::string unescape(const std::string& text, bool& newline) {
  std::string out;
  newline = true;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\\' || i + 1 >= text.size()) {
      out += text[i];
      continue;
    }
    const char c = text[++i];
    if (c == 'n')
      out += '\n';
    else if (c == 'r')
      out += '\r';
    else if (c == '\\')
      out += '\\';
    else if (c == 'c' && i + 1 == text.size())
      newline = false;
    else if (c == 'x' && i + 2 < text.size()) {
      out += static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += '\\';
      out += c;
    }
  }
  return out;
}

void runScript(const fs::path& script) {
  ServerHarness server({}, ::geteuid());
  LineClient client(server.path());
  const bool print = std::getenv("SB_GOLDEN_PRINT") != nullptr;
  std::ifstream in(script);
  REQUIRE(in.good());
  int lineNo = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNo;
    INFO(script.filename().string() << ":" << lineNo << ": " << line);
    if (line.empty() || line[0] == '#') continue;
    const std::string body = line.size() > 2 ? line.substr(2) : "";
    if (line[0] == '>') {
      bool newline = true;
      std::string bytes = unescape(body, newline);
      if (newline) bytes += '\n';
      client.send(bytes);
    } else if (line[0] == '<') {
      const std::string got = client.readLine();
      if (print) std::cout << "< " << got << "\n";
      CHECK(got == body);
    } else if (line.rfind("! frame ", 0) == 0) {
      server.publishFrame(sb::test::scriptedFrame(std::stoull(line.substr(8))));
    } else if (line.rfind("! energy ", 0) == 0) {
      const uint64_t n = std::stoull(line.substr(9));
      server.publishEnergy({n, 0.5 * static_cast<double>(n), 4.0, "scripted"});
    } else if (line == "! map") {  // a hand-made 3 x 2 grid (docs/protocol.md's example)
      server.publishMap(handMadeGrid(300));
    } else if (line == "! map with cloud") {  // the same grid, its frame 1.5 m up, map.bt and three cells
      sb::daemon::MapReport m = handMadeGrid(400);
      m.framePosition = {0.0, 1.5, 0.0};
      m.frameQuaternion = {0.5, -0.5, 0.5, 0.5};
      m.octomap = "/var/lib/slambooster/pass-0001/map.bt";
      m.cloudResolutionM = 0.1;
      m.cloud = {{-3, 0, 2}, {0, 1, 5}, {4, -2, 0}};
      server.publishMap(m);
    } else {
      FAIL("bad script line");
    }
  }
  // Nothing unexpected may come before the reply to this sentinel.
  client.send("?VERSION;\n");
  CHECK(client.readLine() ==
        R"({"class":"VERSION","proto_major":1,"proto_minor":11,"release":"test-release"})");
}

}  // namespace

TEST_CASE("protocol golden scripts", "[daemon][protocol][golden]") {
  std::vector<fs::path> scripts;
  for (const auto& e : fs::directory_iterator(SB_GOLDEN_DIR))
    if (e.path().extension() == ".script") scripts.push_back(e.path());
  std::sort(scripts.begin(), scripts.end());
  REQUIRE(scripts.size() >= 4);
  for (const auto& s : scripts) {
    SECTION(s.filename().string()) {
      runScript(s);
    }
  }
}
