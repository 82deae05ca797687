#pragma once
// Pushes the robot's odometry to slamboosterd over its socket (?ODOM, protocol 1.5; docs/protocol.md), for
// robots without ROS and for `slamboosterctl odom FILE`; the ROS bridge pushes its ~odom_topic the same way.

#include <string>
#include <vector>

#include "client/connection.h"
#include "drivers/odometry_sample.h"

namespace sb::client {

inline constexpr size_t kOdomLineBytes = 3500;  // a request line stays under the daemon's 4096-byte default

// ?ODOM request lines for `samples` (in order, stamps increasing): batches of up to 64 samples, each line at
// most `maxLineBytes` (a single sample always makes a line). Numbers keep every bit (JSON round trip).
std::vector<std::string> odomRequestLines(const std::vector<odometry::OdometrySample>& samples,
                                          size_t maxLineBytes = kOdomLineBytes);

// Sends the samples and waits for each reply; returns the samples accepted. Throws sb::Error with the
// daemon's ERROR message when it refuses a batch (the batches before it stay added).
size_t pushOdometry(Connection& connection, const std::vector<odometry::OdometrySample>& samples,
                    double timeoutSeconds, size_t maxLineBytes = kOdomLineBytes);

}  // namespace sb::client
