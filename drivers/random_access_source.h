#pragma once
// A FrameSource whose frames can be decoded independently and concurrently (a replayed file sequence).
// PrefetchSource decodes such sources on several threads; other sources are read through next() only.

#include <cstddef>

#include "drivers/frame_source.h"

namespace sb {

class RandomAccessSource : public FrameSource {
 public:
  // Number of frames next() yields in total.
  virtual size_t count() const = 0;
  // The i-th frame next() would yield (0 <= i < count()). Safe to call from several threads at once and
  // independent of next(). Throws sb::Error naming the file and frame.
  virtual DepthFrame load(size_t i) const = 0;
};

}  // namespace sb
