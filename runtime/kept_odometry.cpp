#include "runtime/kept_odometry.h"

#include <Eigen/LU>
#include <cmath>

#include "core/error.h"
#include "runtime/map_store_bytes.h"

namespace sb {

namespace {

// Version 1: the calibration, the mount's sums and correction, and the floor's part; version 2 adds the clock's
// and the mount the correction was learnt against.
constexpr size_t kVersion1Bytes = 4 + 8 * (2 + 4 + 2) + 8 * (9 + 5 + 9) + (4 + 8 + 4);
constexpr size_t kVersion2Bytes = kVersion1Bytes + (8 + 4 + 8) + (4 + 8 * 3);  // ... and the mount's up

template <typename M>
void put(mapstore::ByteWriter& w, const M& m) {
  for (int r = 0; r < m.rows(); ++r)
    for (int c = 0; c < m.cols(); ++c) w.f64(m(r, c));
}

template <typename M>
void get(mapstore::ByteReader& r, M& m) {
  for (int i = 0; i < m.rows(); ++i)
    for (int c = 0; c < m.cols(); ++c) m(i, c) = r.f64();
}

}  // namespace

std::vector<uint8_t> encodeKeptOdometry(const KeptOdometry& kept) {
  mapstore::ByteWriter w;
  const odometry::CalibrationState& c = kept.calibration;
  w.i32(c.frames);
  w.f64(c.scaleInfo);
  w.f64(c.scaleVec);
  put(w, c.yawInfo);
  put(w, c.yawVec);
  const odometry::MountCalibration::State& m = kept.mount;
  put(w, m.viewSum);
  put(w, m.wheelSum);
  put(w, m.diffSum);
  for (double v : {m.diffSquares, m.weights, m.weightSquares, m.turnRad, m.standardError}) w.f64(v);
  put(w, m.correction);
  w.i32(m.floorFrames);
  w.f64(m.floorSpreadRad);
  w.i32(m.fromFloor ? 1 : 0);
  const odometry::TimeOffset::State& t = kept.timeOffset;
  w.f64(t.offsetS);
  w.i32(t.learnt ? 1 : 0);
  w.u64(static_cast<uint64_t>(t.frames));
  w.i32(kept.mountUp ? 1 : 0);
  put(w, kept.mountUp.value_or(Eigen::Vector3d::Zero()));
  return std::move(w.bytes);
}

KeptOdometry decodeKeptOdometry(const std::vector<uint8_t>& payload, const std::string& path, uint32_t version) {
  if (version != 1 && version != 2)
    throw Error("map store: '" + path + "' is version " + std::to_string(version) + " of the calibration, this build "
                "reads 1 and 2: use the slambooster that wrote it");
  const size_t expected = version == 1 ? kVersion1Bytes : kVersion2Bytes;
  if (payload.size() != expected)
    throw Error("map store: '" + path + "' holds " + std::to_string(payload.size()) + " bytes of calibration, not " +
                std::to_string(expected) + " (version " + std::to_string(version) + "): corrupt; move it away");
  mapstore::ByteReader r{path, payload};
  KeptOdometry k;
  odometry::CalibrationState& c = k.calibration;
  c.frames = r.i32();
  c.scaleInfo = r.f64();
  c.scaleVec = r.f64();
  get(r, c.yawInfo);
  get(r, c.yawVec);
  odometry::MountCalibration::State& m = k.mount;
  get(r, m.viewSum);
  get(r, m.wheelSum);
  get(r, m.diffSum);
  for (double* v : {&m.diffSquares, &m.weights, &m.weightSquares, &m.turnRad, &m.standardError}) *v = r.f64();
  get(r, m.correction);
  m.floorFrames = r.i32();
  m.floorSpreadRad = r.f64();
  const int32_t fromFloor = r.i32();
  m.fromFloor = fromFloor == 1;
  odometry::TimeOffset::State& t = k.timeOffset;
  int32_t learnt = 0, recorded = 0;
  uint64_t offsetFrames = 0;
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  if (version >= 2) {
    t.offsetS = r.f64();
    learnt = r.i32();
    offsetFrames = r.u64();
    t.learnt = learnt == 1;
    t.frames = static_cast<int64_t>(offsetFrames);
    recorded = r.i32();
    get(r, up);
    if (recorded == 1) k.mountUp = up;
  }
  const bool finite = std::isfinite(c.scaleInfo) && std::isfinite(c.scaleVec) && c.yawInfo.allFinite() &&
                      c.yawVec.allFinite() && m.viewSum.allFinite() && m.wheelSum.allFinite() &&
                      m.diffSum.allFinite() && m.correction.allFinite() && std::isfinite(m.diffSquares) &&
                      std::isfinite(m.weights) && std::isfinite(m.weightSquares) && std::isfinite(m.turnRad) &&
                      std::isfinite(m.standardError) && std::isfinite(m.floorSpreadRad) &&
                      std::isfinite(t.offsetS) && up.allFinite();
  const bool domain = c.frames >= 0 && c.scaleInfo > 0.0 && c.yawInfo(0, 0) > 0.0 && c.yawInfo.determinant() > 0.0 &&
                      std::abs(c.yawInfo(0, 1) - c.yawInfo(1, 0)) <= 1e-9 * c.yawInfo.norm() &&
                      m.weights >= 0.0 && m.turnRad >= 0.0 && m.standardError >= 0.0 &&
                      (m.correction.transpose() * m.correction).isIdentity(1e-6) && m.correction.determinant() > 0.0 &&
                      m.floorFrames >= 0 && m.floorSpreadRad >= 0.0 && (fromFloor == 0 || fromFloor == 1) &&
                      (learnt == 0 || learnt == 1) && offsetFrames <= uint64_t(INT64_MAX) &&
                      (recorded == 0 || (recorded == 1 && std::abs(up.norm() - 1.0) < 1e-6));
  if (!finite || !domain)
    throw Error("map store: '" + path + "' holds a calibration that is not one (a value not finite or out of its "
                "domain): corrupt; move it away");
  return k;
}

}  // namespace sb
