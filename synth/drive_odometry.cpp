#include "synth/drive_odometry.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "synth/rng.h"
#include "synth/stress_moves.h"

namespace sb::synth {

namespace {

using stress::kDegToRad;
using stress::kTwoPi;

constexpr uint64_t kOdometrySalt = 0x0D0E7A1ull;  // the noise's stream, apart from the scene's and the drive's

// A standard normal draw (Box-Muller).
double normal(Rng& rng) {
  const double u1 = std::max(rng.unit(), 1e-300), u2 = rng.unit();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

// Planar pose of the base in its odometry frame.
struct Planar {
  double x = 0.0, y = 0.0, yaw = 0.0;
};

Eigen::Isometry3d toIsometry(const Planar& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.x, p.y, 0.0);
  return T;
}

void check(bool ok, const std::string& what) {
  if (!ok) throw Error("synth odometry: " + what);
}

}  // namespace

void OdometryErrors::validate() const {
  check(std::isfinite(rateHz) && rateHz >= 1.0 && rateHz <= 1000.0, "rate must be 1-1000 Hz");
  check(std::isfinite(scale) && std::abs(scale) <= 0.5, "scale error must be within +-0.5");
  check(std::isfinite(yawScale) && std::abs(yawScale) <= 0.5, "yaw scale error must be within +-0.5");
  check(std::isfinite(yawBiasDegps) && std::abs(yawBiasDegps) <= 30.0, "yaw bias must be within +-30 deg/s");
  check(std::isfinite(noiseMPerSqrtM) && noiseMPerSqrtM >= 0.0 && noiseMPerSqrtM <= 1.0,
        "translation noise must be 0-1 m/sqrt(m)");
  check(std::isfinite(yawNoiseDegPerSqrtS) && yawNoiseDegPerSqrtS >= 0.0 && yawNoiseDegPerSqrtS <= 10.0,
        "yaw noise must be 0-10 deg/sqrt(s)");
  check(std::isfinite(slipAtS), "slip time must be a finite number");
  check(std::isfinite(slipM) && std::abs(slipM) <= 10.0, "slip must be within +-10 m");
}

std::string OdometryErrors::describe() const {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "rate %g Hz, scale error %+g%%, yaw scale error %+g%%, yaw bias %g deg/s, noise %g m/sqrt(m) and "
                "%g deg/sqrt(s)",
                rateHz, 100.0 * scale, 100.0 * yawScale, yawBiasDegps, noiseMPerSqrtM, yawNoiseDegPerSqrtS);
  std::string out = buf;
  if (slipAtS >= 0.0) {
    std::snprintf(buf, sizeof buf, ", a wheel slip of %g m at %g s", slipM, slipAtS);
    out += buf;
  } else {
    out += ", no wheel slip";
  }
  return out;
}

Trajectory driveOdometry(const stress::DrivePath& path, double endS, const OdometryErrors& e, uint64_t seed,
                         double startS, const DriveFaults& faults) {
  e.validate();
  faults.validate();
  const DriveClock clock(path, faults);
  // The whole drive's stream as before; a later start mixes its start (milliseconds) into the seed.
  const uint64_t startMs = startS > 0.0 ? static_cast<uint64_t>(std::llround(startS * 1000.0)) : 0;
  Rng rng(seed * 0x9E3779B97F4A7C15ull + kOdometrySalt + startMs * 0xBF58476D1CE4E5B9ull);
  const double period = 1.0 / e.rateHz;
  // Stamps offset from the frames' (which start at 0 s) by 10-90% of a period.
  const double offset = period * (0.1 + 0.8 * rng.unit());
  // The odometry frame: the base at the start.
  const Eigen::Isometry3d odomFromWorld = path.baseToWorld(clock.at(startS)).inverse();
  const Eigen::Isometry3d mount = assumedMount(path.cameraToBase(), faults);
  const double yawBias = e.yawBiasDegps * kDegToRad, yawNoise = e.yawNoiseDegPerSqrtS * kDegToRad;

  Trajectory out;
  Planar odom;  // the base's reading, integrated
  double previousT = startS;
  Eigen::Isometry3d previousTrue = odomFromWorld * path.baseToWorld(clock.at(startS));
  for (size_t k = 0;; ++k) {
    const double t = startS + offset + static_cast<double>(k) * period;
    const Eigen::Isometry3d trueBase = odomFromWorld * path.baseToWorld(clock.at(t));
    // The true increment in the previous base frame (planar: the base stays on the floor); none while carried.
    const Eigen::Isometry3d d =
        clock.carriedBetween(previousT, t) ? Eigen::Isometry3d::Identity() : previousTrue.inverse() * trueBase;
    const double dx = d.translation().x(), dy = d.translation().y();
    const double dyaw = std::atan2(d.linear()(1, 0), d.linear()(0, 0));
    const double dt = t - previousT, step = std::hypot(dx, dy);
    double mx = (1.0 + e.scale) * dx + e.noiseMPerSqrtM * std::sqrt(step) * normal(rng);
    double my = (1.0 + e.scale) * dy + e.noiseMPerSqrtM * std::sqrt(step) * normal(rng);
    double myaw = (1.0 + e.yawScale) * dyaw + yawBias * dt + yawNoise * std::sqrt(dt) * normal(rng);
    if (e.slipAtS >= 0.0 && e.slipAtS >= previousT && e.slipAtS < t) mx += e.slipM;  // the wheels spin
    if (clock.stalled(t)) mx += (1.0 + e.scale) * faults.stallSpeedMps * dt;  // and spin on against the obstacle
    faults.applyWrongWheels(t, dt, mx, my, myaw);  // after the draws: the noise's stream stays the same
    odom.x += std::cos(odom.yaw) * mx - std::sin(odom.yaw) * my;
    odom.y += std::sin(odom.yaw) * mx + std::cos(odom.yaw) * my;
    odom.yaw += myaw;
    TimedPose sample;
    sample.timestamp = t + faults.latencyS;
    sample.T_camera_to_world = toIsometry(odom) * mount;  // T_camera_to_odom
    out.push_back(sample);
    previousT = t;
    previousTrue = trueBase;
    if (std::min(t, t + faults.latencyS) >= endS) break;
  }
  return out;
}

void writeOdometryFile(const std::string& path, const Trajectory& odometry, const OdometryErrors& errors,
                       uint64_t seed, const DriveFaults& faults) {
  std::ofstream out(path);
  if (!out) throw Error("synth: cannot write '" + path + "': check that the directory exists");
  out << "# timestamp tx ty tz qx qy qz qw: wheel odometry, T_camera_to_odom (metres, seconds on depth.txt's "
         "clock)\n"
      << "# the camera's optical frame (x right, y down, z forward; groundtruth.txt's) in the base's odometry "
         "frame (ROS REP 103: x forward, y left, z up; the base at the sequence's first frame: the drive's start, "
         "or where --frames-from starts it), through the camera mount\n"
      << "# synthetic errors (seed " << seed << "): " << errors.describe() << "\n";
  if (const std::string f = faults.describe(); !f.empty()) out << "# synthetic faults: " << f << "\n";
  for (const TimedPose& p : odometry) out << formatTumLine(p) << "\n";
  if (!out) throw Error("synth: writing '" + path + "' failed (disk full?)");
}

}  // namespace sb::synth
