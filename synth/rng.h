#pragma once
// A small deterministic random generator (splitmix64) whose output is the same on every platform and
// standard library, for procedural scene layout.

#include <cstdint>

namespace sb::synth {

class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    uint64_t x = (state_ += 0x9E3779B97F4A7C15ull);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  // Uniform in [0, 1).
  double unit() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  float uniform(float lo, float hi) { return lo + static_cast<float>(unit()) * (hi - lo); }
  bool chance(double p) { return unit() < p; }
  int index(int n) { return static_cast<int>(unit() * n); }

 private:
  uint64_t state_;
};

}  // namespace sb::synth
