#include "runtime/kept_odometry.h"

#include <Eigen/LU>
#include <cmath>

#include "core/error.h"
#include "runtime/map_store_bytes.h"

namespace sb {

namespace {

constexpr size_t kPayloadBytes = 4 + 8 * (2 + 4 + 2) + 8 * (9 + 5 + 9) + (4 + 8 + 4);  // ... and the floor's

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
  return std::move(w.bytes);
}

KeptOdometry decodeKeptOdometry(const std::vector<uint8_t>& payload, const std::string& path) {
  if (payload.size() != kPayloadBytes)
    throw Error("map store: '" + path + "' holds " + std::to_string(payload.size()) + " bytes of calibration, not " +
                std::to_string(kPayloadBytes) + ": corrupt; move it away");
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
  const bool finite = std::isfinite(c.scaleInfo) && std::isfinite(c.scaleVec) && c.yawInfo.allFinite() &&
                      c.yawVec.allFinite() && m.viewSum.allFinite() && m.wheelSum.allFinite() &&
                      m.diffSum.allFinite() && m.correction.allFinite() && std::isfinite(m.diffSquares) &&
                      std::isfinite(m.weights) && std::isfinite(m.weightSquares) && std::isfinite(m.turnRad) &&
                      std::isfinite(m.standardError) && std::isfinite(m.floorSpreadRad);
  const bool domain = c.frames >= 0 && c.scaleInfo > 0.0 && c.yawInfo(0, 0) > 0.0 && c.yawInfo.determinant() > 0.0 &&
                      std::abs(c.yawInfo(0, 1) - c.yawInfo(1, 0)) <= 1e-9 * c.yawInfo.norm() &&
                      m.weights >= 0.0 && m.turnRad >= 0.0 && m.standardError >= 0.0 &&
                      (m.correction.transpose() * m.correction).isIdentity(1e-6) && m.correction.determinant() > 0.0 &&
                      m.floorFrames >= 0 && m.floorSpreadRad >= 0.0 && (fromFloor == 0 || fromFloor == 1);
  if (!finite || !domain)
    throw Error("map store: '" + path + "' holds a calibration that is not one (a value not finite or out of its "
                "domain): corrupt; move it away");
  return k;
}

}  // namespace sb
