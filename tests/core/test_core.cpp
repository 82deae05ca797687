#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "core/error.h"
#include "core/png_io.h"
#include "core/thread_pool.h"
#include "core/trajectory.h"
#include "tests/support/test_data.h"

using namespace sb;

TEST_CASE("png16 round-trips every value and rejects wrong formats", "[core][png]") {
  const std::string dir = test::scratchDir("png16");
  Image<uint16_t> img(37, 11);
  for (size_t i = 0; i < img.size(); ++i) img.data()[i] = static_cast<uint16_t>(i * 1777u);
  writePng16(dir + "/a.png", img);
  const auto back = readPng16(dir + "/a.png");
  REQUIRE(back.width() == 37);
  REQUIRE(back.height() == 11);
  CHECK(back.pixels() == img.pixels());

  Image<uint8_t> gray8(4, 4, 7);
  writePng8(dir + "/b.png", gray8);
  CHECK_THROWS_WITH(readPng16(dir + "/b.png"), Catch::Contains("8-bit grayscale") && Catch::Contains("b.png"));
  CHECK_THROWS_WITH(readPng16(dir + "/missing.png"), Catch::Contains("missing.png"));

  // Truncated file: first half of a valid PNG.
  {
    std::ifstream in(dir + "/a.png", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream out(dir + "/t.png", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  CHECK_THROWS_WITH(readPng16(dir + "/t.png"), Catch::Contains("t.png"));
}

TEST_CASE("TUM trajectories round-trip and bad lines are named", "[core][trajectory]") {
  const std::string dir = test::scratchDir("tum");
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    TimedPose p;
    p.timestamp = i / 30.0;
    p.T_camera_to_world = Eigen::Translation3d(0.1 * i, -0.2, 1.5) * Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitY());
    t.push_back(p);
  }
  writeTumTrajectory(dir + "/t.txt", t);
  const auto back = readTumTrajectory(dir + "/t.txt");
  REQUIRE(back.size() == t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    CHECK(back[i].timestamp == Approx(t[i].timestamp).margin(1e-6));
    CHECK((back[i].T_camera_to_world.matrix() - t[i].T_camera_to_world.matrix()).norm() < 1e-8);
  }
  {
    std::ofstream bad(dir + "/bad.txt");
    bad << "# c\n0 0 0 0 0 0 0 1\n0.1 1 2 3 0 0\n";
  }
  CHECK_THROWS_WITH(readTumTrajectory(dir + "/bad.txt"), Catch::Contains("bad.txt:3"));
  {
    std::ofstream bad(dir + "/order.txt");
    bad << "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n";
  }
  CHECK_THROWS_WITH(readTumTrajectory(dir + "/order.txt"), Catch::Contains("does not increase"));
}

TEST_CASE("thread pool chunk reductions are identical for any thread count", "[core][thread_pool]") {
  std::vector<float> values(100003);
  for (size_t i = 0; i < values.size(); ++i) values[i] = 1.0f / static_cast<float>(i + 1) * ((i % 3) ? 1.f : -1.f);
  auto reduce = [&](unsigned threads) {
    ThreadPool pool(threads);
    const int chunk = 997;
    std::vector<float> partial(ThreadPool::chunkCount(0, static_cast<int>(values.size()), chunk));
    pool.parallelFor(0, static_cast<int>(values.size()), chunk, [&](int c, int b, int e) {
      float s = 0;
      for (int i = b; i < e; ++i) s += values[i];
      partial[c] = s;
    });
    return std::accumulate(partial.begin(), partial.end(), 0.0f);
  };
  const float one = reduce(1);
  CHECK(reduce(2) == one);
  CHECK(reduce(5) == one);
  // Repeated use of one pool must run every chunk exactly once.
  ThreadPool pool(3);
  for (int round = 0; round < 200; ++round) {
    std::vector<int> hits(1000, 0);
    pool.parallelFor(0, 1000, 7, [&](int, int b, int e) {
      for (int i = b; i < e; ++i) ++hits[i];
    });
    REQUIRE(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
  }
  CHECK_THROWS_AS(pool.parallelFor(0, 10, 1, [](int c, int, int) {
    if (c == 5) throw Error("boom");
  }), Error);
}
