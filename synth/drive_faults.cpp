#include "synth/drive_faults.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "synth/stress_moves.h"

namespace sb::synth {

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw Error("synth drive faults: " + what);
}

constexpr double kPathStepS = 0.01;  // the path's arc length is summed at this step

}  // namespace

void DriveFaults::validate() const {
  check(std::isfinite(stallAtS) && std::isfinite(stallS) && stallS > 0.0 && stallS <= 600.0,
        "a stall lasts more than 0 and at most 600 s");
  check(std::isfinite(stallSpeedMps) && std::abs(stallSpeedMps) <= 5.0, "a stall's wheel speed is within +-5 m/s");
  check(std::isfinite(carriedAtS) && std::isfinite(carriedBackM) && carriedBackM >= 0.0 && carriedBackM <= 1000.0,
        "a carry sets the robot 0-1000 m back");
  check(std::isfinite(latencyS) && std::abs(latencyS) <= 1.0, "the odometry's latency is within +-1 s");
  for (size_t i = 0; i < 3; ++i)
    check(std::isfinite(mountError[i]) && std::abs(mountError[i]) <= 30.0, "a mount error turns at most 30 degrees");
  for (size_t i = 3; i < 6; ++i)
    check(std::isfinite(mountError[i]) && std::abs(mountError[i]) <= 1.0, "a mount error moves at most 1 m");
  check(!(stallAtS >= 0.0 && carriedAtS >= 0.0), "one of a stall and a carry per drive");
}

std::string DriveFaults::describe() const {
  std::string out;
  char buf[200];
  auto add = [&](const char* text) { out += (out.empty() ? "" : ", ") + std::string(text); };
  if (stallAtS >= 0.0) {
    std::snprintf(buf, sizeof buf, "a stall at %g s for %g s, the wheels reading %g m/s", stallAtS, stallS,
                  stallSpeedMps);
    add(buf);
  }
  if (carriedAtS >= 0.0) {
    std::snprintf(buf, sizeof buf, "carried at %g s, set down %g m back", carriedAtS, carriedBackM);
    add(buf);
  }
  if (latencyS != 0.0) {
    std::snprintf(buf, sizeof buf, "stamps %g s late", latencyS);
    add(buf);
  }
  if (mountError != std::array<double, 6>{}) {
    std::snprintf(buf, sizeof buf, "mount off by %g/%g/%g deg and %g/%g/%g m", mountError[0], mountError[1],
                  mountError[2], mountError[3], mountError[4], mountError[5]);
    add(buf);
  }
  return out;
}

DriveClock::DriveClock(const stress::DrivePath& path, const DriveFaults& faults) : faults_(faults) {
  if (faults.carriedAtS < 0.0) return;
  // Back along the path by carriedBackM of arc length (the base's position on the floor).
  double travelled = 0.0, t = std::min(faults.carriedAtS, path.durationS());
  Eigen::Vector3d p = path.baseToWorld(t).translation();
  while (t > 0.0 && travelled < faults.carriedBackM) {
    t = std::max(0.0, t - kPathStepS);
    const Eigen::Vector3d q = path.baseToWorld(t).translation();
    travelled += (q - p).norm();
    p = q;
  }
  backS_ = faults.carriedAtS - t;
}

double DriveClock::at(double t) const {
  if (faults_.stallAtS >= 0.0 && t > faults_.stallAtS) return t - std::min(t - faults_.stallAtS, faults_.stallS);
  if (faults_.carriedAtS >= 0.0 && t >= faults_.carriedAtS) return t - backS_;
  return t;
}

bool DriveClock::stalled(double t) const {
  return faults_.stallAtS >= 0.0 && t > faults_.stallAtS && t <= faults_.stallAtS + faults_.stallS;
}

bool DriveClock::carriedBetween(double t0, double t1) const {
  return faults_.carriedAtS >= 0.0 && t0 < faults_.carriedAtS && t1 >= faults_.carriedAtS;
}

Eigen::Isometry3d assumedMount(const Eigen::Isometry3d& trueMount, const DriveFaults& f) {
  using stress::kDegToRad;
  Eigen::Isometry3d error = Eigen::Isometry3d::Identity();
  error.linear() = (Eigen::AngleAxisd(f.mountError[0] * kDegToRad, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(f.mountError[1] * kDegToRad, Eigen::Vector3d::UnitX()) *
                    Eigen::AngleAxisd(f.mountError[2] * kDegToRad, Eigen::Vector3d::UnitY()))
                       .toRotationMatrix();
  error.translation() = Eigen::Vector3d(f.mountError[3], f.mountError[4], f.mountError[5]);
  return trueMount * error;
}

}  // namespace sb::synth
