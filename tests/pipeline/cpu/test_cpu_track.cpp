// The CPU backend's vectorised track + reduce (pipeline/cpu/cpu_track.h) against kernels/track.h's scalar
// track() and reduce() on the synthetic room: the same per-pixel terms and counts, sums within float
// rounding, at every pyramid level of every csr (widths 328 down to 10, most not multiples of 4), with
// rejected pixels of every kind; and CpuBackend::track bit-identical for any thread count.

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "kernels/track.h"
#include "pipeline/cpu/cpu_backend.h"
#include "pipeline/cpu/cpu_track.h"
#include "pipeline/kernel_args.h"
#include "tests/pipeline/synthetic_room.h"

using sb::test::kRoomDepthScale;

namespace {

constexpr int kBandRows = 8;

// The room seen from a start pose (integrated and raycast: the reference) and a moved pose (preprocessed:
// the input). Raw depth has a hole (pixels without input); the motion leaves border pixels outside the
// reference.
struct RoomTrack {
  sb::PipelineConfig config;
  sb::ThreadPool pool;
  sb::CpuBackend backend;
  Eigen::Isometry3f start, moved;

  RoomTrack(int csr, unsigned threads)
      : config(roomConfig()), pool(threads), backend(config, fullSize(), pool) {
    const sb::test::Room room;
    const sb::Intrinsics k = fullSize();
    Eigen::Isometry3d startD = Eigen::Isometry3d::Identity();
    startD.translation() = Eigen::Vector3d(1.5, 1.5, 0.9);
    const Eigen::Isometry3d movedD = startD * sb::test::motion({0.03, -0.02, 0.01}, 2.0, {0.3, 1.0, -0.2});
    start = startD.cast<float>();
    moved = movedD.cast<float>();
    sb::StageTimes times;
    backend.preprocess(sb::test::renderRoom(room, startD, k).depth, float(1.0 / kRoomDepthScale), csr, times);
    backend.integrate(start, times);
    backend.raycast(start, csr, times);
    sb::DepthRaw raw = sb::test::renderRoom(room, movedD, k).depth;
    for (int y = k.height / 3; y < k.height / 3 + 40; ++y)
      for (int x = k.width / 2; x < k.width / 2 + 50; ++x) raw(x, y) = 0;
    backend.preprocess(raw, float(1.0 / kRoomDepthScale), csr, times);
  }

  static sb::PipelineConfig roomConfig() {
    sb::PipelineConfig c;
    c.volumeSize = 3.0f;
    c.volumeResolution = 128;
    return c;
  }
  static sb::Intrinsics fullSize() { return sb::test::roomIntrinsics(328, 248); }
};

// Copies of one level's maps with patches that make every kind of rejection: reference pixels without a
// normal, input vertices moved 0.5 m away (too far), input normals turned over (bad normal).
struct Maps {
  int width, height;
  std::vector<float> vertex, normal, refVertex, refNormal;
  sb::Intrinsics refK;

  Maps(const RoomTrack& t, int level, bool rejections = true)
      : width(t.backend.levelIntrinsics(level).width),
        height(t.backend.levelIntrinsics(level).height),
        vertex(t.backend.levelVertices(level)),
        normal(t.backend.levelNormals(level)),
        refVertex(t.backend.referenceVertices()),
        refNormal(t.backend.referenceNormals()),
        refK(t.backend.referenceIntrinsics()) {
    if (!rejections) return;
    const int rw = refK.width, rh = refK.height;
    for (int y = rh / 2; y < rh / 2 + std::max(1, rh / 10); ++y)
      for (int x = rw / 5; x < rw / 5 + std::max(1, rw / 10); ++x)
        refNormal[3 * (y * rw + x)] = SB_INVALID_NORMAL;
    for (int y = height / 5; y < height / 5 + std::max(1, height / 10); ++y)
      for (int x = width / 5; x < width / 5 + std::max(1, width / 10); ++x)
        vertex[3 * (y * width + x) + 2] += 0.5f;
    for (int y = 3 * height / 4; y < 3 * height / 4 + std::max(1, height / 10); ++y)
      for (int x = 2 * width / 3; x < 2 * width / 3 + std::max(1, width / 10); ++x)
        for (int c = 0; c < 3; ++c) normal[3 * (y * width + x) + c] *= -1.0f;
  }

  // The first `columns` columns of the input only (a narrower image against the same reference).
  void crop(int columns) {
    std::vector<float> v, n;
    for (int y = 0; y < height; ++y) {
      v.insert(v.end(), vertex.begin() + 3 * y * width, vertex.begin() + 3 * (y * width + columns));
      n.insert(n.end(), normal.begin() + 3 * y * width, normal.begin() + 3 * (y * width + columns));
    }
    vertex.swap(v);
    normal.swap(n);
    width = columns;
  }

  sb::TrackInputs inputs(const sb::PipelineConfig& config, const Eigen::Isometry3f& cameraToWorld,
                         const Eigen::Isometry3f& referencePose) const {
    sb::TrackInputs in;
    in.vertex = vertex.data();
    in.normal = normal.data();
    in.width = width;
    in.height = height;
    in.refVertex = refVertex.data();
    in.refNormal = refNormal.data();
    in.refWidth = refK.width;
    in.refHeight = refK.height;
    in.cameraToWorld = sb::toMat34(cameraToWorld.matrix());
    in.worldToRefPixel = sb::toMat34(
        Eigen::Matrix<float, 3, 4>(sb::cameraMatrix(refK) * referencePose.inverse().matrix().topRows<3>()));
    in.distanceThreshold = config.icpDistanceThreshold;
    in.normalThreshold = config.icpNormalThreshold;
    return in;
  }
};

// kernels/track.h's track() on every pixel (the 8-float rows) and reduce() per row in float, in double across
// rows.
struct Scalar {
  std::vector<float> rows;
  sb::TrackSums sums{};

  explicit Scalar(const sb::TrackInputs& in) : rows(size_t(SB_TRACK_STRIDE) * in.width * in.height) {
    for (int y = 0; y < in.height; ++y) {
      float row[SB_REDUCE_SIZE] = {};
      for (int x = 0; x < in.width; ++x) {
        ::track(rows.data(), in.vertex, in.normal, in.width, in.refVertex, in.refNormal, in.refWidth,
                in.refHeight, in.cameraToWorld, in.worldToRefPixel, in.distanceThreshold, in.normalThreshold,
                x, y);
        ::reduce(row, rows.data(), y * in.width + x);
      }
      for (int i = 0; i < SB_REDUCE_SIZE; ++i) sums[i] += row[i];
    }
  }
};

// The 28 sums of products within float rounding: |a_ij - b_ij| <= tolerance * sqrt(b_ii * b_jj) (the bound of
// |sum a_i a_j| by Cauchy-Schwarz, so terms that cancel are held to the scale of their factors); the counts
// exactly.
void checkSums(const sb::TrackSums& got, const sb::TrackSums& expected, double tolerance) {
  double diagonal[7];
  for (int i = 0, k = 0; i < 7; k += 7 - i, ++i) diagonal[i] = expected[k];
  for (int i = 0, k = 0; i < 7; ++i)
    for (int j = i; j < 7; ++j, ++k) {
      INFO("sum " << k << " (" << i << ", " << j << "): " << got[k] << " vs " << expected[k]);
      CHECK(std::fabs(got[k] - expected[k]) <= tolerance * std::sqrt(diagonal[i] * diagonal[j]));
    }
  for (int k = 28; k < SB_REDUCE_SIZE; ++k) {
    INFO("count " << k);
    CHECK(got[k] == expected[k]);
  }
}

}  // namespace

TEST_CASE("the vectorised track gives every pixel track()'s terms and reduce sums them within float rounding",
          "[pipeline][track]") {
  const int csr = GENERATE(1, 2, 4, 8);
  RoomTrack t(csr, 1);
  // An estimate 5 mm and 0.3 degrees off the true pose, as in an ICP iteration.
  const Eigen::Isometry3f estimate =
      t.moved * sb::test::motion({0.003, 0.004, -0.001}, 0.3, {1.0, 0.2, 0.5}).cast<float>();
  for (int level = 0; level < sb::kPyramidLevels; ++level) {
    Maps maps(t, level);
    for (int columns : {maps.width, maps.width - 1, 7, 3}) {
      if (columns > maps.width || columns < 1) continue;
      Maps cropped = maps;
      cropped.crop(columns);
      const sb::TrackInputs in = cropped.inputs(t.config, estimate, t.start);
      INFO("csr " << csr << ", level " << level << ", " << in.width << " x " << in.height << " pixels");
      const Scalar expected(in);
      if (columns == maps.width) {  // every kind of rejection happens
        int kinds[6] = {};
        for (int i = 0; i < in.width * in.height; ++i) {
          const int code = static_cast<int>(expected.rows[SB_TRACK_STRIDE * i]);
          if (code < 0) ++kinds[-code];
        }
        for (int kind = 1; kind <= 5; ++kind) {
          INFO("pixels of result code " << -kind << ": " << kinds[kind]);
          CHECK(kinds[kind] > 0);
        }
      }
      sb::TrackBand band;
      sb::TrackSums sums{};
      for (int y0 = 0; y0 < in.height; y0 += kBandRows) {
        const int y1 = std::min(in.height, y0 + kBandRows);
        sb::trackBand(in, y0, y1, band);
        REQUIRE(band.stride % 4 == 0);
        REQUIRE(band.stride >= in.width);
        int mismatches = 0;
        for (int y = y0; y < y1; ++y)
          for (int x = 0; x < band.stride; ++x) {
            const float* row =
                x < in.width ? expected.rows.data() + SB_TRACK_STRIDE * (y * in.width + x) : nullptr;
            const bool inlier = row && row[0] == SB_TRACK_INLIER;
            for (int term = 0; term < sb::TrackBand::kTrackTerms; ++term) {
              const float value =
                  band.values[((y - y0) * sb::TrackBand::kTrackTerms + term) * band.stride + x];
              if (value != (inlier ? row[1 + term] : 0.0f)) ++mismatches;  // padding and rejected pixels: 0
            }
          }
        INFO("rows " << y0 << "-" << y1);
        CHECK(mismatches == 0);
        sb::TrackSums partial{};
        sb::reduceBand(band, partial);
        for (int i = 0; i < SB_REDUCE_SIZE; ++i) sums[i] += partial[i];
      }
      checkSums(sums, expected.sums, 1e-5);
    }
  }
}

TEST_CASE("CpuBackend::track matches track() + reduce() and is bit-identical for 1, 2 and 3 threads",
          "[pipeline][track][determinism]") {
  const int csr = GENERATE(1, 4);
  RoomTrack one(csr, 1), two(csr, 2), three(csr, 3);
  for (int level = 0; level < sb::kPyramidLevels; ++level) {
    INFO("csr " << csr << ", level " << level);
    sb::StageTimes times;
    const sb::TrackSums a = one.backend.track(level, one.moved, one.start, times);
    const sb::TrackSums b = two.backend.track(level, two.moved, two.start, times);
    const sb::TrackSums c = three.backend.track(level, three.moved, three.start, times);
    for (int i = 0; i < SB_REDUCE_SIZE; ++i) {
      CHECK(a[i] == b[i]);
      CHECK(a[i] == c[i]);
    }
    const Maps maps(one, level, false);
    checkSums(a, Scalar(maps.inputs(one.config, one.moved, one.start)).sums, 1e-5);
    CHECK(a[28] > 0);
    CHECK(times[sb::Stage::track] > 0);
  }
}

TEST_CASE("CpuBackend::blockSums is trackBlock() + reduce() over the last track; block 1 gives track's J^T J",
          "[pipeline][track][quality]") {
  const int csr = GENERATE(1, 4);
  RoomTrack one(csr, 1), three(csr, 3);
  sb::StageTimes times;
  CHECK_THROWS_WITH(one.backend.blockSums(4, times), Catch::Contains("without a track"));
  for (int level = 0; level < sb::kPyramidLevels; ++level) {
    const sb::TrackSums icp = one.backend.track(level, one.moved, one.start, times);
    three.backend.track(level, three.moved, three.start, times);
    const Maps maps(one, level, false);
    const Scalar scalar(maps.inputs(one.config, one.moved, one.start));
    for (const int block : {1, 3, 8}) {  // 3: the last blocks of a row and of the image are partial
      INFO("csr " << csr << ", level " << level << ", block " << block);
      const sb::TrackSums got = one.backend.blockSums(block, times);
      const sb::TrackSums again = three.backend.blockSums(block, times);
      for (int i = 0; i < SB_REDUCE_SIZE; ++i) CHECK(got[i] == again[i]);  // any thread count
      // kernels/track.h's trackBlock over the scalar rows, reduce() per row of blocks.
      const int bx = (maps.width + block - 1) / block, by = (maps.height + block - 1) / block;
      std::vector<float> rows(size_t(SB_TRACK_STRIDE) * bx * by);
      sb::TrackSums expected{};
      for (int y = 0; y < by; ++y) {
        float partial[SB_REDUCE_SIZE] = {};
        for (int x = 0; x < bx; ++x) {
          ::trackBlock(rows.data(), scalar.rows.data(), maps.width, maps.height, block, x, y);
          ::reduce(partial, rows.data(), y * bx + x);
        }
        for (int i = 0; i < SB_REDUCE_SIZE; ++i) expected[i] += partial[i];
      }
      CHECK(expected[28] > 0);
      checkSums(got, expected, 1e-5);
      if (block == 1) {
        for (int i = 7; i <= 28; ++i) CHECK(got[i] == Approx(icp[i]).epsilon(1e-5).margin(1e-6 * icp[7]));
      } else {
        CHECK(got[28] < icp[28]);  // blocks, not pixels
      }
    }
  }
  one.backend.preprocess(sb::test::renderRoom(sb::test::Room{}, one.start.cast<double>(), RoomTrack::fullSize()).depth,
                         float(1.0 / kRoomDepthScale), csr, times);
  CHECK_THROWS_WITH(one.backend.blockSums(4, times), Catch::Contains("without a track"));
}

TEST_CASE("squaredDistanceLimit: sqrtf(s) > d exactly when s > the limit", "[pipeline][track]") {
  for (float d : {0.1f, 0.05f, 1e-4f, 0.3f, 1.0f, 3.7f, 10.0f}) {
    const float limit = sb::squaredDistanceLimit(d);
    INFO("d " << d << ", limit " << limit);
    CHECK(std::sqrt(limit) <= d);
    CHECK(std::sqrt(std::nextafter(limit, INFINITY)) > d);
    float s = d * d;
    for (int i = 0; i < 64; ++i) s = std::nextafter(s, 0.0f);
    for (int i = 0; i < 128; ++i, s = std::nextafter(s, INFINITY)) CHECK((std::sqrt(s) > d) == (s > limit));
  }
  CHECK(sb::squaredDistanceLimit(0.0f) == 0.0f);
}
