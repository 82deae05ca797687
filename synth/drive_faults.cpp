#include "synth/drive_faults.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/error.h"
#include "synth/stress_moves.h"

namespace sb::synth {

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw Error("synth drive faults: " + what);
}

constexpr double kPathStepS = 0.01;  // the path's arc length is summed at this step
constexpr double kMaxWrongGyroDegps = 180.0;  // stated ranges of the wrong wheels' value
constexpr double kMaxWrongScale = 10.0;
constexpr double kDefaultWrongGyroDegps = 20.0;  // issue 52's attack: a 20 deg/s gyro bias ...
constexpr double kDefaultWrongScale = 2.0;       // ... and steps x2

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
  if (wrong == WrongWheels::None) return;
  check(std::isfinite(wrongAtS) && wrongAtS >= 0.0, "wrong wheels start at a time of at least 0 s");
  check(std::isfinite(wrongS) && wrongS > 0.0 && wrongS <= 600.0, "wrong wheels last more than 0 and at most 600 s");
  if (wrong == WrongWheels::Gyro)
    check(std::isfinite(wrongValue) && std::abs(wrongValue) <= kMaxWrongGyroDegps,
          "a wrong gyro's bias is within +-180 deg/s");
  if (wrong == WrongWheels::Scaled)
    check(std::isfinite(wrongValue) && std::abs(wrongValue) <= kMaxWrongScale,
          "wrong wheels' scale factor is within +-10");
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
  if (wrong != WrongWheels::None) {
    std::snprintf(buf, sizeof buf, "wheels %s from %g s for %g s", wrongWheelsName(wrong).c_str(), wrongAtS, wrongS);
    std::string text = buf;
    if (wrong == WrongWheels::Gyro) {
      std::snprintf(buf, sizeof buf, " (a gyro bias of %g deg/s)", wrongValue);
      text += buf;
    } else if (wrong == WrongWheels::Scaled) {
      std::snprintf(buf, sizeof buf, " (steps times %g)", wrongValue);
      text += buf;
    }
    add(text.c_str());
  }
  return out;
}

bool DriveFaults::wrongAt(double t) const {
  return wrong != WrongWheels::None && t > wrongAtS && t <= wrongAtS + wrongS;
}

void DriveFaults::applyWrongWheels(double t, double dt, double& dx, double& dy, double& dyaw) const {
  if (!wrongAt(t)) return;
  switch (wrong) {
    case WrongWheels::None:
      break;
    case WrongWheels::Reversed:
      dx = -dx, dy = -dy, dyaw = -dyaw;
      break;
    case WrongWheels::Zero:
      dx = dy = dyaw = 0.0;
      break;
    case WrongWheels::Gyro:
      dyaw += wrongValue * stress::kDegToRad * dt;
      break;
    case WrongWheels::Scaled:
      dx *= wrongValue, dy *= wrongValue, dyaw *= wrongValue;
      break;
  }
}

std::string wrongWheelsName(WrongWheels kind) {
  switch (kind) {
    case WrongWheels::None:
      return "none";
    case WrongWheels::Reversed:
      return "reversed";
    case WrongWheels::Zero:
      return "zero";
    case WrongWheels::Gyro:
      return "gyro";
    case WrongWheels::Scaled:
      return "scaled";
  }
  return "none";
}

WrongWheels parseWrongWheels(const std::string& name) {
  for (WrongWheels k : {WrongWheels::Reversed, WrongWheels::Zero, WrongWheels::Gyro, WrongWheels::Scaled})
    if (name == wrongWheelsName(k)) return k;
  throw Error("synth: --odom-wrong's KIND '" + name + "' is not one of reversed, zero, gyro, scaled");
}

void parseWrongWheelsOption(const std::string& text, DriveFaults& faults) {
  const std::string usage = "synth: --odom-wrong '" + text + "': expected KIND,AT,SECONDS[,VALUE] (KIND reversed, "
                            "zero, gyro or scaled; AT >= 0 and SECONDS > 0 seconds; VALUE gyro's deg/s or scaled's "
                            "factor)";
  std::vector<std::string> fields;
  for (size_t begin = 0;;) {
    const size_t comma = text.find(',', begin);
    fields.push_back(text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  if (fields.size() < 3 || fields.size() > 4) throw Error(usage);
  const WrongWheels kind = parseWrongWheels(fields[0]);
  std::vector<double> numbers;
  for (size_t i = 1; i < fields.size(); ++i) {
    char* end = nullptr;
    const double v = std::strtod(fields[i].c_str(), &end);
    if (fields[i].empty() || *end != '\0' || !std::isfinite(v))
      throw Error(usage + ": '" + fields[i] + "' is not a number");
    numbers.push_back(v);
  }
  const bool takesValue = kind == WrongWheels::Gyro || kind == WrongWheels::Scaled;
  if (numbers.size() == 3 && !takesValue) throw Error(usage + ": " + fields[0] + " takes no VALUE");
  faults.wrong = kind;
  faults.wrongAtS = numbers[0];
  faults.wrongS = numbers[1];
  faults.wrongValue = numbers.size() == 3 ? numbers[2]
                      : kind == WrongWheels::Gyro ? kDefaultWrongGyroDegps
                      : kind == WrongWheels::Scaled ? kDefaultWrongScale
                                                    : 0.0;
  try {
    faults.validate();
  } catch (const Error& e) {
    throw Error(usage + ": " + e.what());
  }
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
