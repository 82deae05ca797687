#include "drivers/tum_cut.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/trajectory.h"
#include "drivers/calibration.h"
#include "drivers/tum_index.h"
#include "drivers/tum_layout.h"
#include "drivers/tum_reader.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

constexpr double kRadToDeg = 180.0 / 3.141592653589793;

size_t parseIndex(const std::string& item, const std::string& number) {
  size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || number[0] == '-' || number[0] == '+')
    throw Error("frame list: \"" + item + "\" is not a frame index or range A-B (0-based, inclusive)");
  return static_cast<size_t>(v);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// The reference pose nearest to `t` within `maxDiff`, or nullptr. `gt` is sorted by time.
const TimedPose* nearestPose(const Trajectory& gt, double t, double maxDiff) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t,
                                   [](const TimedPose& p, double time) { return p.timestamp < time; });
  const TimedPose* best = nullptr;
  if (it != gt.end()) best = &*it;
  if (it != gt.begin() && (!best || t - std::prev(it)->timestamp < best->timestamp - t))
    best = &*std::prev(it);
  return best && std::abs(best->timestamp - t) <= maxDiff ? best : nullptr;
}

std::string formatTimestamp(double seconds) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", seconds);
  return buf;
}

bool inside(const fs::path& child, const fs::path& parent) {
  const auto [end, ignored] = std::mismatch(parent.begin(), parent.end(), child.begin(), child.end());
  return end == parent.end();
}

}  // namespace

std::vector<FrameRange> parseFrameList(const std::string& text) {
  std::vector<FrameRange> ranges;
  std::stringstream in(text);
  for (std::string raw; std::getline(in, raw, ',');) {
    const std::string item = trim(raw);
    const size_t dash = item.find('-', 1);
    FrameRange r;
    if (dash == std::string::npos) {
      r.first = r.last = parseIndex(item, item);
    } else {
      r.first = parseIndex(item, trim(item.substr(0, dash)));
      r.last = parseIndex(item, trim(item.substr(dash + 1)));
      if (r.last < r.first)
        throw Error("frame list: range \"" + item + "\" ends before it starts; write it as first-last");
    }
    ranges.push_back(r);
  }
  if (ranges.empty() || (!text.empty() && text.back() == ','))
    throw Error("frame list \"" + text + "\" names no frames; give e.g. 0-299,100-199");
  return ranges;
}

CutResult cutTumSequence(const std::string& sourceDir, const std::vector<FrameRange>& ranges,
                         const std::string& outDir, const CutOptions& options) {
  if (ranges.empty()) throw Error("cut: the frame list names no frames");
  // Opening the source checks its index, its images and its calibration, and finds its ground truth.
  const TumReader source(sourceDir, SequenceOptions{});
  const fs::path src = fs::absolute(sourceDir).lexically_normal();
  const bool associations =
      !fs::is_regular_file(src / tum::kIndexFile) && fs::is_regular_file(src / tum::kAssociationsFile);
  const std::vector<TumIndexEntry> index =
      readTumIndex((src / (associations ? tum::kAssociationsFile : tum::kIndexFile)).string(), associations);
  if (index.size() < 2)
    throw Error("cut: source '" + sourceDir + "' has one frame: no frame rate to give the cut's timestamps");
  for (const FrameRange& r : ranges)
    if (r.last >= index.size())
      throw Error("cut: frame " + std::to_string(r.last) + " is past the end of '" + sourceDir + "' (" +
                  std::to_string(index.size()) + " frames, 0-" + std::to_string(index.size() - 1) + ")");
  std::vector<double> intervals;
  for (size_t i = 1; i < index.size(); ++i) intervals.push_back(index[i].timestamp - index[i - 1].timestamp);
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2),
                   intervals.end());
  CutResult result;
  result.frameIntervalS = intervals[intervals.size() / 2];

  const fs::path out = fs::absolute(outDir).lexically_normal();
  if (inside(out, src) || inside(src, out))
    throw Error("cut: the output '" + outDir + "' and the source '" + sourceDir +
                "' must not contain one another; write the cut elsewhere");
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_empty(out, ec)) {
    if (!options.overwrite)
      throw Error("cut: '" + outDir + "' is not empty; choose another directory or allow overwriting");
    // The files a cut writes: `overwrite` removes exactly these.
    for (const char* name : {tum::kIndexFile, tum::kCalibrationFile, tum::kGroundTruthFile, tum::kSegmentsFile})
      fs::remove(out / name, ec);
  }
  fs::create_directories(out, ec);
  if (ec) throw Error("cut: cannot create '" + outDir + "': " + ec.message());

  const std::string gtPath = source.info().groundTruthPath;
  const Trajectory gt = gtPath.empty() ? Trajectory{} : readTumTrajectory(gtPath);
  std::ofstream depth(out / tum::kIndexFile), truth, segments(out / tum::kSegmentsFile);
  depth << "# timestamp filename (cut of " << src.string() << ")\n";
  segments << "label,begin_frame,end_frame\n";
  if (!gt.empty()) {
    truth.open(out / tum::kGroundTruthFile);
    truth << "# timestamp tx ty tz qx qy qz qw (camera-to-world, metres; reference poses of " << gtPath
          << " at the cut's timestamps)\n";
  }
  const double t0 = index[ranges.front().first].timestamp;
  const TimedPose* previousPose = nullptr;
  size_t previousSource = 0;
  for (const FrameRange& r : ranges) {
    segments << "src-" << r.first << "-" << r.last << "," << result.frames << ","
             << result.frames + (r.last - r.first + 1) << "\n";
    for (size_t s = r.first; s <= r.last; ++s) {
      const TumIndexEntry& e = index[s];
      const double t = t0 + static_cast<double>(result.frames) * result.frameIntervalS;
      const fs::path png =
          fs::path(e.file).is_absolute() ? fs::path(e.file) : (src / e.file).lexically_normal();
      depth << formatTimestamp(t) << " " << png.string() << "\n";
      const TimedPose* pose = nearestPose(gt, e.timestamp, options.maxTimeDifferenceS);
      if (s == r.first && result.frames > 0) {
        CutJump jump{result.frames, previousSource, s, -1.0, -1.0};
        if (pose && previousPose) {
          jump.translationM = (pose->position() - previousPose->position()).norm();
          jump.rotationDeg = Eigen::AngleAxisd(previousPose->T_camera_to_world.linear().transpose() *
                                               pose->T_camera_to_world.linear())
                                 .angle() *
                             kRadToDeg;
        }
        result.jumps.push_back(jump);
      }
      if (pose) {
        TimedPose moved = *pose;
        moved.timestamp = t;
        truth << formatTumLine(moved) << "\n";
        ++result.groundTruthPoses;
      }
      previousPose = pose;
      previousSource = s;
      ++result.frames;
    }
  }
  if (fs::is_regular_file(src / tum::kCalibrationFile))
    fs::copy_file(src / tum::kCalibrationFile, out / tum::kCalibrationFile, fs::copy_options::overwrite_existing, ec);
  else
    writeCalibration((out / tum::kCalibrationFile).string(), source.info());
  depth.flush();
  truth.flush();
  segments.flush();
  if (ec || !depth || !segments || (!gt.empty() && !truth))
    throw Error("cut: cannot write the cut into '" + outDir + "'" +
                (ec ? ": " + ec.message() : std::string()));
  return result;
}

}  // namespace sb
