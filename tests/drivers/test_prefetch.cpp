#include <catch2/catch.hpp>
#include <atomic>
#include <filesystem>

#include "core/error.h"
#include "core/png_io.h"
#include "drivers/prefetch_source.h"
#include "drivers/sequence.h"
#include "tests/drivers/fixtures.h"
#include "tests/support/test_data.h"

using namespace sb;

namespace {

// Yields frames 0..frames-1 (1x1, value = index), throwing at `failAt` if set; counts calls to next().
class CountingSource : public FrameSource {
 public:
  CountingSource(size_t frames, std::optional<size_t> failAt, std::atomic<size_t>& produced)
      : frames_(frames), failAt_(failAt), produced_(produced) {
    info_.format = "counting";
    info_.frameCount = frames;
  }
  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override {
    const size_t i = cursor_++;
    ++produced_;
    if (failAt_ && i == *failAt_) throw Error("counting source: frame " + std::to_string(i) + " is bad");
    if (i >= frames_) return std::nullopt;
    DepthFrame f;
    f.index = i;
    f.timestamp = static_cast<double>(i);
    f.depth = DepthRaw(1, 1, static_cast<uint16_t>(i));
    return f;
  }

 private:
  SequenceInfo info_;
  size_t frames_;
  std::optional<size_t> failAt_;
  std::atomic<size_t>& produced_;
  size_t cursor_ = 0;
};

}  // namespace

TEST_CASE("prefetching yields exactly the frames of direct reading", "[drivers][prefetch]") {
  const std::string dir = test::writePatternSequence(test::scratchDir("prefetch_same") + "/seq", 12, test::smallInfo());
  SequenceOptions direct;
  direct.prefetch = false;
  SequenceOptions ahead;
  ahead.prefetch = true;
  ahead.prefetchDepth = 3;
  auto a = openSequence(dir, direct);
  auto b = openSequence(dir, ahead);
  CHECK(dynamic_cast<PrefetchSource*>(b.get()) != nullptr);
  CHECK(b->info().frameCount == a->info().frameCount);
  CHECK(b->info().intrinsics.fx == a->info().intrinsics.fx);
  size_t n = 0;
  for (;;) {
    auto fa = a->next();
    auto fb = b->next();
    REQUIRE(fa.has_value() == fb.has_value());
    if (!fa) break;
    CHECK(fa->index == fb->index);
    CHECK(fa->timestamp == fb->timestamp);
    CHECK(fa->depth.pixels() == fb->depth.pixels());
    ++n;
  }
  CHECK(n == 12);
  CHECK_FALSE(b->next());
}

TEST_CASE("prefetching delivers an error after the frames before it, then again", "[drivers][prefetch]") {
  std::atomic<size_t> produced{0};
  PrefetchSource source(std::make_unique<CountingSource>(10, 4, produced), 2);
  for (size_t i = 0; i < 4; ++i) {
    const auto f = source.next();
    REQUIRE(f);
    CHECK(f->index == i);
    CHECK(f->depth(0, 0) == i);
  }
  CHECK_THROWS_WITH(source.next(), Catch::Contains("frame 4 is bad"));
  CHECK_THROWS_WITH(source.next(), Catch::Contains("frame 4 is bad"));
}

TEST_CASE("prefetching a real sequence reports a truncated PNG at its frame", "[drivers][prefetch]") {
  const std::string dir = test::writePatternSequence(test::scratchDir("prefetch_error") + "/seq", 6, test::smallInfo());
  const std::string png = dir + "/depth/000003.png";
  const std::string bytes = test::readText(png);
  test::writeText(png, bytes.substr(0, bytes.size() / 2));
  SequenceOptions o;
  o.prefetchDepth = 4;
  auto source = openSequence(dir, o);
  for (size_t i = 0; i < 3; ++i) REQUIRE(source->next()->index == i);
  CHECK_THROWS_WITH(source->next(), Catch::Contains("000003.png") && Catch::Contains("frame 3"));
}

TEST_CASE("prefetching stays within its depth and can be destroyed mid-sequence", "[drivers][prefetch]") {
  std::atomic<size_t> produced{0};
  const size_t depth = 3;
  {
    PrefetchSource source(std::make_unique<CountingSource>(1000000, std::nullopt, produced), depth);
    for (size_t consumed = 1; consumed <= 20; ++consumed) {
      REQUIRE(source.next()->index == consumed - 1);
      // At most `depth` frames queued plus one being decoded.
      CHECK(produced.load() <= consumed + depth + 1);
    }
  }  // destroyed with the worker blocked on a full queue
  CHECK(produced.load() <= 20 + depth + 1);

  // Destroyed before anything was read, and at the end.
  { PrefetchSource idle(std::make_unique<CountingSource>(5, std::nullopt, produced), 1); }
  PrefetchSource done(std::make_unique<CountingSource>(2, std::nullopt, produced), 8);
  CHECK(done.next());
  CHECK(done.next());
  CHECK_FALSE(done.next());
  CHECK_FALSE(done.next());
}

TEST_CASE("PrefetchSource rejects a zero depth", "[drivers][prefetch]") {
  std::atomic<size_t> produced{0};
  CHECK_THROWS_AS(PrefetchSource(std::make_unique<CountingSource>(1, std::nullopt, produced), 0), Error);
}
