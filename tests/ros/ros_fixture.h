#pragma once
// Shared by the ROS system tests: a real ROS master (Debian's rosmaster) on a free port, this test program as
// a ROS node of it, the bridge as a child process, and readers of the outputs. Builds on the daemon system
// tests' fixture (tests/daemon/daemon_e2e.h, which each test includes: binaries, the short synthetic
// sequence, socket directories).

#include <ros/ros.h>
#include <sensor_msgs/Image.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "drivers/frame_source.h"
#include "tests/daemon/process.h"
#include "tests/support/test_data.h"

namespace sb::test::ros_e2e {

inline const std::string kBridge = sb::test::testBinary("SB_TEST_SLAMBOOSTER_ROS", SB_SLAMBOOSTER_ROS_BIN);

// A free TCP port on the loopback interface (bound and released: a race with other programs is possible but
// harmless here, the master would fail to start and the test says so).
int freePort();

// rosmaster --core on a free port, with its logs and ROS_HOME in `dir`; stopped (SIGINT, then killed) at the end.
class RosMaster {
 public:
  explicit RosMaster(const std::string& dir);
  // On `port` (a master started again where an earlier one was).
  RosMaster(const std::string& dir, int port);
  ~RosMaster();
  const std::string& uri() const { return uri_; }
  // The environment a child process needs to join this master.
  std::vector<std::string> env() const;

 private:
  std::string dir_, uri_;
  std::unique_ptr<ChildProcess> process_;
};

// Joins this test program to `master` as a node (once per process: roscpp allows one init), and waits until
// the master answers. Throws std::runtime_error when it does not within a few seconds.
void joinMaster(const RosMaster& master, const std::string& nodeName);

// Starts slambooster_ros as node /slambooster with the given private parameters ("name:=value").
std::unique_ptr<ChildProcess> startBridge(const RosMaster& master, const std::vector<std::string>& params,
                                          const std::string& logPath);

// Polls `done` every 10 ms (spinning nothing: callbacks run on the test's AsyncSpinner) for up to `seconds`.
bool waitFor(const std::function<bool()>& done, double seconds);

// The data lines of a TUM trajectory file ("timestamp tx ty tz qx qy qz qw"), in file order.
std::vector<std::string> trajectoryLines(const std::string& path);

// A pipeline config (the daemon tests' settings) that also carries `sequence`'s volume hints
// (calibration.json): a bag or a pushed stream has none, the TUM directory does; with them in the config both
// reconstruct in the same volume. Written to dir/pipeline.json; returns its path.
std::string pipelineConfigWithHints(const std::string& dir, const std::string& sequence, int volumeResolution = 64,
                                    const std::string& knobs = "csr=2,ir=1");

// daemonArgs(...) with the pipeline config replaced by `config`.
std::vector<std::string> withPipelineConfig(std::vector<std::string> args, const std::string& config);

// Values of one TUM trajectory line.
std::vector<double> lineValues(const std::string& line);

// A depth frame as a camera driver publishes it: 32FC1 metres (NaN for no reading) in camera_depth_optical_frame.
sensor_msgs::Image depthImage(const sb::DepthFrame& frame, double depthScale, const ros::Time& stamp);

}  // namespace sb::test::ros_e2e
