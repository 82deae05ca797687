#include "ros/master_watch.h"

#include <ros/ros.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace sb::ros_bridge {

MasterWatch::MasterWatch(double periodSeconds) : periodSeconds_(periodSeconds), thread_([this] { loop(); }) {}

MasterWatch::~MasterWatch() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

bool MasterWatch::registered() const {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = ros::this_node::getName();
  // false for a master that answers "unknown node" (status code -1) as for one that does not answer.
  return ros::master::execute("lookupNode", args, result, payload, false);
}

void MasterWatch::loop() {
  bool unreachable = false;
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::duration<double>(periodSeconds_), [this] { return stop_; })) {
    lock.unlock();
    if (!ros::master::check()) {
      if (!unreachable) ROS_WARN("the ROS master at %s does not answer; waiting for it", ros::master::getURI().c_str());
      unreachable = true;
    } else if (ros::ok() && !ros::isShuttingDown() && !registered()) {  // not our own unregistering at shutdown
      ROS_FATAL("the ROS master at %s was restarted: it does not know node %s, whose topics were registered with "
                "the master before; exiting %d for the supervisor to start the bridge again (roslaunch "
                "respawn=\"true\", systemd Restart=on-failure)",
                ros::master::getURI().c_str(), ros::this_node::getName().c_str(), kMasterRestartedExit);
      std::fflush(nullptr);
      ::_exit(kMasterRestartedExit);  // roscpp cannot register again in this process
    } else if (unreachable) {
      ROS_INFO("the ROS master at %s answers again and still knows this node", ros::master::getURI().c_str());
      unreachable = false;
    }
    lock.lock();
  }
}

}  // namespace sb::ros_bridge
