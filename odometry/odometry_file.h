#pragma once
// An odometry.txt read as the frames need it (issue 53): a day's log at 100 Hz is 10^7 lines, and holding it
// whole took about 1 GB per 10^6 lines. readOdometryFile (odometry_track.h) checks the whole file once, line by
// line (its errors name the file and line, before the run starts), then feeds a track from a second reader, so
// that at most kOdometryFileWindow samples are held, whatever the file's length.

#include <cstddef>
#include <memory>
#include <string>

#include "core/trajectory.h"
#include "odometry/odometry_track.h"

namespace sb::odometry {

// Samples held of a file: 164 s at 100 Hz, about 7 MB. A frame whose stamp is older than the window's oldest
// sample (further back than this behind the newest frame) has no odometry.
inline constexpr size_t kOdometryFileWindow = 16384;

// The samples of a TUM-format odometry.txt in order, one line in memory at a time.
class OdometryFileSource : public OdometrySampleSource {
 public:
  explicit OdometryFileSource(const std::string& path) : reader_(path) {}
  bool next(OdometrySample& sample) override;

 private:
  TumTrajectoryReader reader_;
};

// Reads the whole file once without keeping it: the number of samples. Throws sb::Error naming the file and
// line on bad input (as readTumTrajectory).
size_t checkOdometryFile(const std::string& path);

}  // namespace sb::odometry
