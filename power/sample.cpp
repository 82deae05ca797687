#include "power/sample.h"

#include "core/error.h"

namespace sb::power {

const char* sampleKindName(SampleKind kind) {
  return kind == SampleKind::intervalAverage ? "interval_average" : "instantaneous";
}

SampleKind parseSampleKind(const std::string& name, const std::string& where) {
  if (name == "instantaneous") return SampleKind::instantaneous;
  if (name == "interval_average") return SampleKind::intervalAverage;
  throw Error(where + ": sample kind '" + name + "' is not one of: instantaneous, interval_average");
}

}  // namespace sb::power
