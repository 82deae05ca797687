#include "pipeline/block_distance.h"

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace sb {

namespace {

using Word = uint64_t;
constexpr int kWordBits = 64;

// The 8 x 8 bit transpose of `x` read as 8 rows of 8 bits (row j = byte j, bit c of it = bit 8 j + c):
// afterwards byte c holds bit c of every input byte (Hacker's Delight, transpose8).
Word transpose8(Word x) {
  Word t = (x ^ (x >> 7)) & 0x00AA00AA00AA00AAull;
  x = x ^ t ^ (t << 7);
  t = (x ^ (x >> 14)) & 0x0000CCCC0000CCCCull;
  x = x ^ t ^ (t << 14);
  t = (x ^ (x >> 28)) & 0x00000000F0F0F0F0ull;
  return x ^ t ^ (t << 28);
}

// planes[c * words + w]: bit c of the masks of one row of n blocks as bits (block x: bit x % 64 of word x / 64).
void maskPlanes(const uint8_t* masks, int n, int words, Word* planes) {
  for (int w = 0; w < words; ++w) {
    Word plane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int g = 0; g < kWordBits / 8; ++g) {
      const int x0 = w * kWordBits + 8 * g;
      if (x0 >= n) break;
      Word bytes = 0;
      if (x0 + 8 <= n) {
        const uint8_t* m = masks + x0;
        bytes = Word{m[0]} | Word{m[1]} << 8 | Word{m[2]} << 16 | Word{m[3]} << 24 | Word{m[4]} << 32 |
                Word{m[5]} << 40 | Word{m[6]} << 48 | Word{m[7]} << 56;
      } else {
        for (int j = 0; x0 + j < n; ++j) bytes |= Word{masks[x0 + j]} << (8 * j);
      }
      if (bytes == 0) continue;  // most blocks: no surface
      const Word columns = transpose8(bytes);
      for (int c = 0; c < 8; ++c) plane[c] |= ((columns >> (8 * c)) & 0xFFu) << (8 * g);
    }
    for (int c = 0; c < 8; ++c) planes[c * words + w] = plane[c];
  }
}

// out = each row of `in` dilated by one block along x (bits x - 1, x, x + 1), limited to the row's n bits.
void dilateX(const Word* in, size_t rows, int words, Word last, Word* out) {
  if (words == 1) {  // n <= 64: the default volumes
    for (size_t i = 0; i < rows; ++i) out[i] = (in[i] | (in[i] << 1) | (in[i] >> 1)) & last;
    return;
  }
  for (size_t r = 0; r < rows; ++r) {
    const Word* s = in + r * words;
    Word* o = out + r * words;
    for (int w = 0; w < words; ++w) {
      const Word below = w > 0 ? s[w - 1] >> (kWordBits - 1) : 0;
      const Word above = w + 1 < words ? s[w + 1] << (kWordBits - 1) : 0;
      o[w] = s[w] | (s[w] << 1) | below | (s[w] >> 1) | above;
    }
    o[words - 1] &= last;
  }
}

// out[i] = in[i] | in[i - stride] | in[i + stride] over `count` words (the neighbours that exist, per run of
// `run` words: a slice of rows or the whole grid of slices).
void dilateAlong(const Word* in, size_t count, size_t stride, size_t run, Word* out) {
  for (size_t start = 0; start < count; start += run) {
    const Word* s = in + start;
    Word* o = out + start;
    for (size_t i = 0; i < std::min(stride, run); ++i) o[i] = s[i];
    for (size_t i = stride; i < run; ++i) o[i] = s[i] | s[i - stride];
    for (size_t i = 0; i + stride < run; ++i) o[i] |= s[i + stride];
  }
}

// Writes `value` to the bytes of `row` (64 per word) whose bits are set in `bits`, a run at a time.
void writeRuns(Word bits, uint8_t value, uint8_t* row) {
  while (bits != 0) {
    const int lo = __builtin_ctzll(bits);
    const Word rest = ~(bits >> lo);
    const int length = rest == 0 ? kWordBits - lo : __builtin_ctzll(rest);
    std::memset(row + lo, value, static_cast<size_t>(length));
    bits &= length == kWordBits ? 0 : ~(((Word{1} << length) - 1) << lo);
  }
}

}  // namespace

void computeBlockDistance(const std::vector<uint8_t>& masks, int n, std::vector<uint8_t>& distance,
                          ThreadPool& pool, int maxDistance) {
  const size_t nn = static_cast<size_t>(n) * n;
  const int words = (n + kWordBits - 1) / kWordBits;
  const Word last = n % kWordBits == 0 ? ~Word{0} : (Word{1} << (n % kWordBits)) - 1;
  const size_t rows = nn, cells = rows * words;  // rows (y, z) at y + n z, `words` words each
  const uint8_t cap = static_cast<uint8_t>(std::clamp(maxDistance, 1, static_cast<int>(kNoSurfaceDistance)));
  distance.assign(nn * n, cap);
  // planes: per row, its masks' 8 bit planes (later scratch of the dilations); reached: per row, the blocks
  // within the current radius.
  std::vector<Word> planes(cells * 8), reached(cells), grown(cells);
  pool.parallelFor(0, n, 1, [&](int, int z0, int z1) {
    for (int z = z0; z < z1; ++z)
      for (int y = 0; y < n; ++y) {
        const size_t row = static_cast<size_t>(y) + static_cast<size_t>(z) * n;
        maskPlanes(&masks[row * n], n, words, &planes[row * 8 * words]);
      }
  });
  // Radius 0: block b has surface when bit c of the mask of block b + c is set (c in {0, 1}^3, blocks that
  // exist): plane c of row (y + cy, z + cz), moved down by cx blocks.
  pool.parallelFor(0, n, 1, [&](int, int z0, int z1) {
    for (int z = z0; z < z1; ++z)
      for (int y = 0; y < n; ++y) {
        Word* seeds = &reached[(static_cast<size_t>(y) + static_cast<size_t>(z) * n) * words];
        const auto plane = [&](int c) {  // plane c of the row it is read from, or nullptr
          const int qy = y + ((c >> 1) & 1), qz = z + (c >> 2);
          return qy < n && qz < n ? &planes[((static_cast<size_t>(qy) + static_cast<size_t>(qz) * n) * 8 + c) * words]
                                  : nullptr;
        };
        const Word* p[8];
        for (int c = 0; c < 8; ++c) p[c] = plane(c);
        for (int w = 0; w < words; ++w) {
          Word seed = 0;
          for (int c = 0; c < 8; ++c) {
            if (!p[c]) continue;
            // cx = 1: block x takes bit x + 1 of the plane.
            seed |= (c & 1) == 0 ? p[c][w] : (p[c][w] >> 1) | (w + 1 < words ? p[c][w + 1] << (kWordBits - 1) : 0);
          }
          seeds[w] = seed;
        }
        uint8_t* out = &distance[static_cast<size_t>(y) * n + static_cast<size_t>(z) * nn];
        for (int w = 0; w < words; ++w) writeRuns(seeds[w], 0, out + static_cast<size_t>(w) * kWordBits);
      }
  });
  // Radius r: the blocks within Chebyshev distance r of one with surface are those within r - 1 dilated by one
  // block on each axis (x: the words shifted by one bit; y and z: or of the neighbouring rows); those the
  // dilation adds are at distance r. Stops at the cap, or when a dilation adds nothing (all reached, or no
  // surface at all).
  const size_t rowWords = static_cast<size_t>(words), sliceWords = static_cast<size_t>(n) * words;
  for (int r = 1; r < cap; ++r) {
    // grown: reached dilated along x, then y (rows of a slice), then z (slices).
    dilateX(reached.data(), rows, words, last, grown.data());
    dilateAlong(grown.data(), cells, rowWords, sliceWords, planes.data());
    dilateAlong(planes.data(), cells, sliceWords, cells, grown.data());
    bool any = false;
    for (size_t i = 0; i < cells; ++i) {
      const Word added = grown[i] & ~reached[i];
      if (added == 0) continue;
      any = true;
      reached[i] = grown[i];
      const size_t row = i / rowWords, w = i % rowWords;
      const size_t y = row % n, z = row / n;
      writeRuns(added, static_cast<uint8_t>(r), &distance[y * n + z * nn + w * kWordBits]);
    }
    if (!any) break;
  }
}

}  // namespace sb
