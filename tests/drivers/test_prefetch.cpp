#include <atomic>
#include <catch2/catch.hpp>
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

// The same frames through RandomAccessSource::load, so that several workers decode at once.
class CountingRandomSource : public RandomAccessSource {
 public:
  CountingRandomSource(size_t frames, std::optional<size_t> failAt, std::atomic<size_t>& produced)
      : frames_(frames), failAt_(failAt), produced_(produced) {}
  const SequenceInfo& info() const override { return info_; }
  std::optional<DepthFrame> next() override {
    if (cursor_ >= frames_) return std::nullopt;
    return load(cursor_++);
  }
  size_t count() const override { return frames_; }
  DepthFrame load(size_t i) const override {
    ++produced_;
    if (failAt_ && i == *failAt_) throw Error("random source: frame " + std::to_string(i) + " is bad");
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

std::unique_ptr<FrameSource> makeSource(bool randomAccess, size_t frames, std::optional<size_t> failAt,
                                        std::atomic<size_t>& produced) {
  if (randomAccess) return std::make_unique<CountingRandomSource>(frames, failAt, produced);
  return std::make_unique<CountingSource>(frames, failAt, produced);
}

}  // namespace

TEST_CASE("prefetching yields exactly the frames of direct reading", "[drivers][prefetch]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("prefetch_same") + "/seq", 12, test::smallInfo());
  SequenceOptions direct;
  direct.prefetch = false;
  SequenceOptions ahead;
  ahead.prefetch = true;
  ahead.prefetchDepth = 3;
  ahead.prefetchThreads = GENERATE(1, 2, 4);
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
  const bool randomAccess = GENERATE(false, true);
  const size_t threads = GENERATE(1, 3);
  std::atomic<size_t> produced{0};
  PrefetchSource source(makeSource(randomAccess, 10, 4, produced), 2, threads);
  for (size_t i = 0; i < 4; ++i) {
    const auto f = source.next();
    REQUIRE(f);
    CHECK(f->index == i);
    CHECK(f->depth(0, 0) == i);
  }
  CHECK_THROWS_WITH(source.next(), Catch::Contains("frame 4 is bad"));
  CHECK_THROWS_WITH(source.next(), Catch::Contains("frame 4 is bad"));
}

TEST_CASE("prefetching many frames on several threads keeps the order", "[drivers][prefetch]") {
  std::atomic<size_t> produced{0};
  const size_t frames = 500;
  PrefetchSource source(std::make_unique<CountingRandomSource>(frames, std::nullopt, produced), 5, 4);
  for (size_t i = 0; i < frames; ++i) {
    const auto f = source.next();
    REQUIRE(f);
    REQUIRE(f->index == i);
  }
  CHECK_FALSE(source.next());
  CHECK(produced.load() == frames);  // each frame decoded exactly once
}

TEST_CASE("prefetching a real sequence reports a truncated PNG at its frame", "[drivers][prefetch]") {
  const std::string dir =
      test::writePatternSequence(test::scratchDir("prefetch_error") + "/seq", 6, test::smallInfo());
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
  const bool randomAccess = GENERATE(false, true);
  std::atomic<size_t> produced{0};
  const size_t depth = 3;
  {
    PrefetchSource source(makeSource(randomAccess, 1000000, std::nullopt, produced), depth, 2);
    for (size_t consumed = 1; consumed <= 20; ++consumed) {
      REQUIRE(source.next()->index == consumed - 1);
      // Workers claim a frame only while fewer than `depth` are ahead of the caller.
      CHECK(produced.load() <= consumed + depth);
    }
  }  // destroyed with the worker blocked on a full queue
  CHECK(produced.load() <= 20 + depth);

  // Destroyed before anything was read, and at the end.
  { PrefetchSource idle(makeSource(randomAccess, 5, std::nullopt, produced), 1, 2); }
  PrefetchSource done(makeSource(randomAccess, 2, std::nullopt, produced), 8, 2);
  CHECK(done.next());
  CHECK(done.next());
  CHECK_FALSE(done.next());
  CHECK_FALSE(done.next());
}

TEST_CASE("PrefetchSource rejects a zero depth", "[drivers][prefetch]") {
  std::atomic<size_t> produced{0};
  CHECK_THROWS_AS(PrefetchSource(std::make_unique<CountingSource>(1, std::nullopt, produced), 0), Error);
  CHECK_THROWS_AS(PrefetchSource(std::make_unique<CountingSource>(1, std::nullopt, produced), 1, 0), Error);
}
