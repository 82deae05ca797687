#pragma once
// ?ODOM's samples into the live odometry track (odometry/odometry_track.h) that the SLAM thread reads: the
// event loop's side of the socket door (daemon/odom_request.h parses the request).

#include <nlohmann/json.hpp>

#include "daemon/odom_request.h"
#include "odometry/odometry_track.h"

namespace sb::daemon {

// The track's sample of one request sample (quaternion normalised, covariance row-major 6x6).
odometry::OdometrySample toOdometrySample(const OdomSample& sample);

// Adds the samples in order, each refused alone when it cannot be placed (odometry_track.h: a stamp not after
// the newest, or past the clock's leap), and returns the ODOM reply fields (without "class"): accepted, samples
// held and the track's capacity, the oldest and newest stamps held, and with refusals "refused" (how many) and
// "refused_first" (the first's message). Throws sb::Error naming the first refused sample when none was
// accepted.
nlohmann::json addOdomSamples(odometry::OdometryTrack& track, const OdomRequest& request);

}  // namespace sb::daemon
