#pragma once
// Watches the ROS master (issue 44 B3c). roscpp registers the node, its topics and its services once, with
// the master it finds at start; a master that is killed and started again knows nothing of them, and roscpp
// never registers again, so nothing the bridge publishes would reach anyone. Every period the watch asks the
// master for this node (lookupNode): while the master does not answer it says so once and waits; when a
// master answers that does not know this node, it says so and ends the bridge with kMasterRestartedExit, for
// its supervisor (roslaunch respawn="true", systemd Restart=on-failure) to start it again, registering with
// the new master (README "With ROS").

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace sb::ros_bridge {

// The exit status of a bridge whose master was restarted.
constexpr int kMasterRestartedExit = 3;

class MasterWatch {
 public:
  explicit MasterWatch(double periodSeconds = 1.0);
  ~MasterWatch();  // stops the thread
  MasterWatch(const MasterWatch&) = delete;
  MasterWatch& operator=(const MasterWatch&) = delete;

 private:
  void loop();
  bool registered() const;  // false only when a master answered and does not know this node

  double periodSeconds_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace sb::ros_bridge
