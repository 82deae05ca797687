#pragma once
// Pushes the robot's odometry to slamboosterd over its socket (?ODOM, protocol 1.5; docs/protocol.md), for
// robots without ROS and for `slamboosterctl odom FILE`; the ROS bridge pushes its ~odom_topic the same way.

#include <optional>
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

// What the daemon said of the samples pushed: taken, refused alone (odometry_track.h's rules), and what its
// track holds after the last batch (it keeps `capacity` samples, the oldest going first).
struct OdomPushResult {
  size_t accepted = 0, refused = 0;
  std::string firstRefused;  // the daemon's message for the first refused sample
  size_t held = 0, capacity = 0;
  std::optional<double> oldest, newest;  // stamps held
};

// Sends the samples and waits for each reply. Throws sb::Error with the daemon's ERROR message when it
// refuses a whole batch (the batches before it stay added).
OdomPushResult pushOdometry(Connection& connection, const std::vector<odometry::OdometrySample>& samples,
                    double timeoutSeconds, size_t maxLineBytes = kOdomLineBytes);

}  // namespace sb::client
