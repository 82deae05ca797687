#include "tests/ros/ros_fixture.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "drivers/sequence.h"

namespace sb::test::ros_e2e {

int freePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
    throw std::runtime_error("cannot find a free TCP port");
  const int port = ntohs(addr.sin_port);
  close(fd);
  return port;
}

RosMaster::RosMaster(const std::string& dir) : RosMaster(dir, freePort()) {}

RosMaster::RosMaster(const std::string& dir, int port) : dir_(dir) {
  uri_ = "http://127.0.0.1:" + std::to_string(port) + "/";
  process_ = std::make_unique<ChildProcess>(
      std::vector<std::string>{SB_ROSMASTER_BIN, "--core", "-p", std::to_string(port), "-w", "3"}, env(),
      dir_ + "/rosmaster.log");
}

RosMaster::~RosMaster() {
  process_->signal(SIGINT);
  process_->wait(5.0);
}

std::vector<std::string> RosMaster::env() const {
  return {"ROS_MASTER_URI=" + uri_, "ROS_HOME=" + dir_, "ROS_LOG_DIR=" + dir_, "ROS_IP=127.0.0.1",
          "ROSCONSOLE_STDOUT_LINE_BUFFERED=1"};
}

void joinMaster(const RosMaster& master, const std::string& nodeName) {
  for (const auto& kv : master.env()) {
    const auto eq = kv.find('=');
    setenv(kv.substr(0, eq).c_str(), kv.substr(eq + 1).c_str(), 1);
  }
  int argc = 1;
  char arg0[] = "test";
  char* argv[] = {arg0, nullptr};
  ros::init(argc, argv, nodeName, ros::init_options::NoSigintHandler | ros::init_options::NoRosout);
  if (!waitFor([] { return ros::master::check(); }, 15.0))
    throw std::runtime_error("the ROS master at " + master.uri() + " did not answer within 15 s");
  ros::start();
}

std::unique_ptr<ChildProcess> startBridge(const RosMaster& master, const std::vector<std::string>& params,
                                          const std::string& logPath) {
  std::vector<std::string> argv{kBridge, "__name:=slambooster"};
  for (const auto& p : params) argv.push_back("_" + p);
  return std::make_unique<ChildProcess>(argv, master.env(), logPath);
}

bool waitFor(const std::function<bool()>& done, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

std::vector<std::string> trajectoryLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  return lines;
}

std::string pipelineConfigWithHints(const std::string& dir, const std::string& sequence, int volumeResolution,
                                    const std::string& knobs) {
  sb::SequenceOptions o;
  o.prefetch = false;
  const auto info = sb::openSequence(sequence, o)->info();
  if (!info.volumeSize || !info.volumeInitialPosition)
    throw std::runtime_error("the test sequence has no volume hints in calibration.json");
  const nlohmann::json j = {{"volume_resolution", volumeResolution}, {"knobs", knobs}, {"volume_size_m", *info.volumeSize},
                            {"initial_position", *info.volumeInitialPosition}};
  const std::string path = dir + "/pipeline.json";
  std::ofstream(path) << j.dump();
  return path;
}

std::vector<std::string> withPipelineConfig(std::vector<std::string> args, const std::string& config) {
  for (auto& a : args)
    if (a.rfind("slam.pipeline_config=", 0) == 0) a = "slam.pipeline_config=" + config;
  return args;
}

std::vector<double> lineValues(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

sensor_msgs::Image depthImage(const sb::DepthFrame& f, double depthScale, const ros::Time& stamp) {
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = "camera_depth_optical_frame";
  m.width = static_cast<uint32_t>(f.depth.width());
  m.height = static_cast<uint32_t>(f.depth.height());
  m.encoding = "32FC1";
  m.step = m.width * sizeof(float);
  m.data.resize(static_cast<size_t>(m.step) * m.height);
  for (size_t i = 0; i < f.depth.size(); ++i) {
    const uint16_t raw = f.depth.pixels()[i];
    const float metres = raw ? static_cast<float>(raw / depthScale) : std::numeric_limits<float>::quiet_NaN();
    std::memcpy(m.data.data() + i * sizeof(float), &metres, sizeof metres);
  }
  return m;
}

}  // namespace sb::test::ros_e2e
