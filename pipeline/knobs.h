#pragma once
// The approximation knobs of KinectFusion (architecture.md D2). They are passed to the pipeline per frame and
// may change between any two frames.

#include <array>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace sb {

struct Knobs {
  int csr = 1;                                // compute size ratio: input subsampled by 1, 2, 4 or 8
  double icpThreshold = 1e-5;                 // ICP early stop when the update norm is below this (0 = never)
  std::array<int, 3> pyramidIterations{10, 5, 4};  // max ICP iterations per level: finest, mid, coarsest
  int trackingRate = 1;                       // track every n-th frame
  int integrationRate = 2;                    // integrate every n-th frame

  bool operator==(const Knobs& o) const {
    return csr == o.csr && icpThreshold == o.icpThreshold && pyramidIterations == o.pyramidIterations &&
           trackingRate == o.trackingRate && integrationRate == o.integrationRate;
  }
  bool operator!=(const Knobs& o) const { return !(*this == o); }
};

constexpr int kMaxIterations = 100;
constexpr int kMaxRate = 1000;
// A compute size ratio the pipeline runs at: 1, 2, 4 or 8.
constexpr bool validCsr(int csr) { return csr == 1 || csr == 2 || csr == 4 || csr == 8; }

// Each knob once, as odometry/odometry_config.cpp keeps its keys: its name, its member, its range. Everything
// that reads or writes knobs by name is made from this table: validateKnobs, parseKnobs and formatKnobs, the
// pins (runtime/knob_pins.h, the daemon's ?CONTROL) and a knob set's JSON (forEachKnobField: frames.jsonl,
// summary.json, the daemon's KNOBS, and their readers in report/, ros/ and slamboosterctl). The ICP iterations
// are one knob per pyramid level, pd0 (finest) to pd2, written together as kIterationsKnob (pd=10:5:4 in a knob
// string, "pd": [10, 5, 4] in JSON). tests/docs/check_knob_names.py fails on a knob name written anywhere else.
struct KnobKey {
  const char* name;
  int Knobs::*whole;        // the member of a whole-number knob, or nullptr
  double Knobs::*real;      // the member of a real-valued knob, or nullptr
  int level;                // neither: the level of Knobs::pyramidIterations (pd0..pd2); else -1
  double minimum, maximum;  // valid values, inclusive
  bool powerOfTwo;          // only powers of two in the range (csr: 1, 2, 4 or 8)
  const char* unit;         // after the range in messages ("" when none)

  bool isWhole() const { return real == nullptr; }
  double value(const Knobs& k) const {
    return real ? k.*real : whole ? k.*whole : k.pyramidIterations[static_cast<size_t>(level)];
  }
  void set(Knobs& k, double v) const {  // a whole-number knob takes v truncated
    if (real)
      k.*real = v;
    else if (whole)
      k.*whole = static_cast<int>(v);
    else
      k.pyramidIterations[static_cast<size_t>(level)] = static_cast<int>(v);
  }
};

inline constexpr const char* kIterationsKnob = "pd";
inline constexpr KnobKey kKnobKeys[] = {
    {"csr", &Knobs::csr, nullptr, -1, 1, 8, true, ""},
    {"icp", nullptr, &Knobs::icpThreshold, -1, 0.0, 1.0, false, ""},
    {"pd0", nullptr, nullptr, 0, 1, kMaxIterations, false, " iterations"},
    {"pd1", nullptr, nullptr, 1, 0, kMaxIterations, false, " iterations"},
    {"pd2", nullptr, nullptr, 2, 0, kMaxIterations, false, " iterations"},
    {"tr", &Knobs::trackingRate, nullptr, -1, 1, kMaxRate, false, ""},
    {"ir", &Knobs::integrationRate, nullptr, -1, 1, kMaxRate, false, ""},
};

// The knob `name` of the table (pd0..pd2 for the iterations), or nullptr.
const KnobKey* findKnob(const std::string& name);
// The table's row of a member (knobKey(&Knobs::csr).name is "csr") or of one level's iterations.
constexpr const KnobKey& knobKey(int Knobs::*member) {
  for (const KnobKey& key : kKnobKeys)
    if (key.whole == member) return key;
  return kKnobKeys[0];  // not reached: every member is in the table (the static_asserts below)
}
constexpr const KnobKey& knobKey(double Knobs::*member) {
  for (const KnobKey& key : kKnobKeys)
    if (key.real == member) return key;
  return kKnobKeys[0];
}
constexpr const KnobKey& iterationsKey(int level) {
  for (const KnobKey& key : kKnobKeys)
    if (!key.whole && !key.real && key.level == level) return key;
  return kKnobKeys[0];
}
static_assert(knobKey(&Knobs::csr).whole == &Knobs::csr && knobKey(&Knobs::trackingRate).whole == &Knobs::trackingRate &&
              knobKey(&Knobs::integrationRate).whole == &Knobs::integrationRate &&
              knobKey(&Knobs::icpThreshold).real == &Knobs::icpThreshold && iterationsKey(0).level == 0 &&
              iterationsKey(1).level == 1 && iterationsKey(2).level == 2,
              "every member of Knobs has its row in kKnobKeys");

// Calls field(name, member) for each knob as a knob set is written (JSON, knob strings), in the table's order:
// csr (int), icp (double), pd (std::array<int, 3>, finest level first), tr (int), ir (int). `K` is Knobs or
// const Knobs. The JSON writers and readers of a knob set are made from it.
template <typename K, typename Field>
void forEachKnobField(K& knobs, Field&& field) {
  for (const KnobKey& key : kKnobKeys) {
    if (key.whole)
      field(key.name, knobs.*key.whole);
    else if (key.real)
      field(key.name, knobs.*key.real);
    else if (key.level == 0)
      field(kIterationsKnob, knobs.pyramidIterations);
  }
}

// "default" (SLAMBench's settings) or "accurate"; throws sb::Error naming the preset otherwise.
Knobs knobPreset(const std::string& name);

// Throws sb::Error naming the knob, its value and the allowed values when a knob is out of range.
void validateKnobs(const Knobs& knobs);

// Parses "csr=2,icp=1e-4,pd=8:5:4,tr=1,ir=2" (any subset, any order) on top of `base` and validates the
// result. Throws sb::Error naming the offending item.
Knobs parseKnobs(const std::string& text, const Knobs& base = Knobs{});

// The same syntax, every knob: "csr=1,icp=1e-05,pd=10:5:4,tr=1,ir=2".
std::string formatKnobs(const Knobs& knobs);

// The knob names that can be pinned one by one (the daemon's ?CONTROL, runtime/knob_pins.h): the table's, in
// its order.
const std::vector<std::string>& pinnableKnobs();

// A knob set as frames.jsonl, summary.json and the daemon's KNOBS write it (forEachKnobField):
// {"csr": 1, "icp": 1e-5, "pd": [10, 5, 4], "tr": 1, "ir": 2}.
nlohmann::json knobsToJson(const Knobs& knobs);

}  // namespace sb
