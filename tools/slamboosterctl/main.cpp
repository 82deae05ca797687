// slamboosterctl: the command-line client of slamboosterd's socket (docs/protocol.md).
//   slamboosterctl watch [--count N] [--no-pose] [--no-knobs] [--no-energy]
//   slamboosterctl poll | status
//   slamboosterctl control [--controller NAME] [--pin KNOB=VALUE]... [--unpin KNOB|all]...
//   slamboosterctl odom FILE   (push a TUM-format odometry.txt with ?ODOM)
// Human-readable by default; --json prints the daemon's JSON lines as they are. Exit codes: 0 ok,
// 1 the daemon refused (ERROR) or could not be reached, 2 usage.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "client/connection.h"
#include "client/odometry_pusher.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/trajectory.h"
#include "tools/slamboosterctl/human_format.h"

namespace {

struct Options {
  std::string socket = "/run/slambooster/slambooster.sock";
  bool json = false;
  double timeout = 5.0;
  // watch
  uint64_t count = 0;
  bool noPose = false, noKnobs = false, noEnergy = false;
  // control
  std::string controller;
  std::vector<std::string> pins, unpins;
  // odom
  std::string odometryFile;
};

void print(const Options& o, const nlohmann::json& m) {
  std::cout << (o.json ? m.dump() : sb::ctl::formatMessage(m)) << std::endl;
}

int requestReply(const Options& o, const std::string& request, const std::string& cls) {
  sb::client::Connection c(o.socket, o.timeout);
  c.send(request);
  const nlohmann::json reply = c.reply(cls, o.timeout);
  if (reply.value("class", "") == "ERROR") {
    std::cerr << "slamboosterctl: slamboosterd refused: " << reply.value("message", "") << "\n";
    if (o.json) print(o, reply);
    return 1;
  }
  if (o.json) {
    print(o, reply);
  } else if (cls == "POLL") {
    for (const char* key : {"pose", "knobs", "energy"})
      if (reply.contains(key) && reply[key].is_object()) print(o, reply[key]);
    if (!reply.contains("pose") || !reply["pose"].is_object()) std::cout << "no frame processed yet\n";
  } else if (cls == "CONTROL") {
    std::cout << "controller " << reply.value("controller", "?") << ", pinned "
              << (reply.contains("pinned") ? reply["pinned"].dump() : "{}") << "\n";
  } else {
    print(o, reply);
  }
  return 0;
}

int watch(const Options& o) {
  sb::client::Connection c(o.socket, o.timeout);
  const nlohmann::json w = {
      {"enable", true}, {"pose", !o.noPose}, {"knobs", !o.noKnobs}, {"energy", !o.noEnergy}};
  c.send("?WATCH=" + w.dump());
  const nlohmann::json ack = c.reply("WATCH", o.timeout);
  if (ack.value("class", "") == "ERROR") {
    std::cerr << "slamboosterctl: slamboosterd refused: " << ack.value("message", "") << "\n";
    return 1;
  }
  uint64_t frames = 0;
  while (o.count == 0 || frames < o.count) {
    auto m = c.next(0);  // streams may pause (a replay that ended): wait as long as it takes
    if (!m) {
      std::cerr << "slamboosterctl: slamboosterd closed the connection\n";
      return 0;
    }
    print(o, *m);
    const std::string cls = m->value("class", "");
    // --count counts frames: POSE, or KNOBS when poses are not watched, or ENERGY when only energy is.
    if (cls == (!o.noPose ? "POSE" : !o.noKnobs ? "KNOBS" : "ENERGY")) ++frames;
  }
  return 0;
}

std::string controlRequest(const Options& o) {
  nlohmann::json j = nlohmann::json::object();
  if (!o.controller.empty()) j["controller"] = o.controller;
  for (const auto& p : o.pins) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CLI::ValidationError("--pin", "'" + p + "' must be KNOB=VALUE, e.g. csr=2");
    const nlohmann::json value = nlohmann::json::parse(p.substr(eq + 1), nullptr, false);
    if (!value.is_number()) throw CLI::ValidationError("--pin", "'" + p + "': the value must be a number");
    j["pin"][p.substr(0, eq)] = value;
  }
  if (std::find(o.unpins.begin(), o.unpins.end(), "all") != o.unpins.end())
    j["unpin"] = "all";
  else if (!o.unpins.empty())
    j["unpin"] = o.unpins;
  if (j.empty()) throw CLI::ValidationError("control", "give --controller, --pin or --unpin");
  return "?CONTROL=" + j.dump();
}

// Pushes an odometry.txt (TUM format, T_camera_to_odom) to the daemon's live odometry, and says what the
// daemon kept: it holds a bounded number of samples (the oldest going first), so a file longer than that loses
// its start (issue 53: 10,000 samples were reported accepted while 4,096 were kept). Exit 1 when samples were
// refused or are no longer held.
int pushOdometryFile(const Options& o) {
  std::vector<sb::odometry::OdometrySample> samples;
  for (const sb::TimedPose& p : sb::readTumTrajectory(o.odometryFile))
    samples.push_back({p.timestamp, p.T_camera_to_world, std::nullopt});
  sb::client::Connection c(o.socket, o.timeout);
  const sb::client::OdomPushResult r = sb::client::pushOdometry(c, samples, o.timeout);
  size_t dropped = 0;  // pushed samples older than the oldest held
  if (r.oldest)
    for (const auto& s : samples) dropped += s.timestamp < *r.oldest;
  const size_t kept = r.accepted >= dropped ? r.accepted - dropped : 0;
  if (o.json) {
    nlohmann::json j = {{"class", "ODOM"}, {"sent", samples.size()}, {"accepted", r.accepted}, {"refused", r.refused},
                        {"kept", kept}, {"dropped", dropped}, {"held", r.held}, {"capacity", r.capacity}};
    if (r.oldest) j["oldest"] = *r.oldest;
    if (r.newest) j["newest"] = *r.newest;
    if (!r.firstRefused.empty()) j["refused_first"] = r.firstRefused;
    print(o, j);
  } else {
    std::cout << "odometry: " << samples.size() << " samples of " << o.odometryFile << " sent, " << r.accepted
              << " accepted";
    if (r.refused) std::cout << ", " << r.refused << " refused (the first: " << r.firstRefused << ")";
    std::cout << "; the daemon holds " << r.held << " samples (at most " << r.capacity << ")";
    if (r.oldest && r.newest) std::cout << " from " << std::fixed << *r.oldest << " to " << *r.newest << " s";
    std::cout << "\n";
    if (dropped)
      std::cout << "odometry: the " << dropped << " oldest samples of " << o.odometryFile << " are no longer held ("
                << kept << " kept): push a file's samples shortly before the frames that need them, at most "
                << r.capacity << " ahead\n";
  }
  return r.refused || dropped ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slamboosterctl: watch and control slamboosterd through its Unix socket"};
  Options o;
  app.set_version_flag("--version", std::string(SB_VERSION));
  app.add_option("--socket", o.socket, "slamboosterd's socket")->capture_default_str();
  app.add_flag("--json", o.json, "Print the daemon's JSON lines as they are");
  app.add_option("--timeout", o.timeout, "Seconds to wait for a reply")->capture_default_str();
  app.require_subcommand(1);
  auto* watchCmd = app.add_subcommand("watch", "Stream POSE, KNOBS and ENERGY as frames are processed");
  watchCmd->add_option("--count", o.count, "Stop after this many frames: POSE messages, or KNOBS without POSE, or ENERGY alone (0 = until the daemon stops)");
  watchCmd->add_flag("--no-pose", o.noPose, "Do not stream POSE");
  watchCmd->add_flag("--no-knobs", o.noKnobs, "Do not stream KNOBS");
  watchCmd->add_flag("--no-energy", o.noEnergy, "Do not stream ENERGY");
  app.add_subcommand("poll", "The latest pose, knobs and energy");
  app.add_subcommand("status", "Source, controller, meter, frame rate, drops, uptime");
  auto* controlCmd = app.add_subcommand("control",
                                        "Switch the controller or pin knobs (root, the daemon's user or "
                                        "the socket.control_group)");
  controlCmd->add_option("--controller", o.controller, "Switch to this controller");
  controlCmd->add_option("--pin", o.pins, "Pin a knob: csr, icp, pd0, pd1, pd2, tr or ir, e.g. --pin csr=2");
  controlCmd->add_option("--unpin", o.unpins, "Unpin a knob, or all");
  auto* odomCmd = app.add_subcommand("odom", "Push the robot's odometry: a TUM-format odometry.txt (the camera's "
                                             "poses in the odometry frame, on the depth frames' clock)");
  odomCmd->add_option("file", o.odometryFile, "odometry.txt")->required();
  try {
    app.parse(argc, argv);
    if (*odomCmd) return pushOdometryFile(o);
    if (*watchCmd) return watch(o);
    if (app.got_subcommand("poll")) return requestReply(o, "?POLL;", "POLL");
    if (app.got_subcommand("status")) return requestReply(o, "?STATUS;", "STATUS");
    return requestReply(o, controlRequest(o), "CONTROL");
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::cerr << "slamboosterctl: " << sb::printable(e.what()) << "\n";
    return 1;
  }
}
