// One place per default (issue 42): the relocaliser's settings are keys of the pipeline config
// (pipeline/config.h) and RelocaliserParams takes them from there; it repeats none of their defaults.

#include <catch2/catch.hpp>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "reloc/relocaliser.h"

namespace {

std::string readSource(const std::string& rel) {
  std::ifstream in(std::string(SB_SOURCE_DIR) + "/" + rel);
  REQUIRE(in.good());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text between `open` and the next `close`.
std::string between(const std::string& text, const std::string& open, const std::string& close) {
  const size_t a = text.find(open);
  REQUIRE(a != std::string::npos);
  const size_t b = text.find(close, a);
  REQUIRE(b != std::string::npos);
  return text.substr(a, b - a);
}

std::set<std::string> matches(const std::string& text, const std::regex& re) {
  std::set<std::string> names;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1].str());
  return names;
}

}  // namespace

TEST_CASE("RelocaliserParams repeats no default of the pipeline config", "[reloc][defaults]") {
  // The members the constructor from PipelineConfig sets ...
  const std::string ctor = between(readSource("reloc/relocaliser.cpp"),
                                   "RelocaliserParams::RelocaliserParams(const PipelineConfig& c)", "{}");
  const auto fromConfig = matches(ctor, std::regex(R"((\w+)\(\s*(?:static_cast<\w+>\()?c\.\w+)"));
  REQUIRE(fromConfig.size() >= 9);
  // ... have no initialiser of their own in the struct (a second default that could drift from config.h's).
  const std::string decl = between(readSource("reloc/relocaliser.h"), "struct RelocaliserParams {", "};");
  const auto initialised = matches(decl, std::regex(R"((\w+)\s*=\s*[^=;]+;)"));
  for (const auto& name : fromConfig) {
    INFO("RelocaliserParams::" << name << " is set from the pipeline config and must not have a default of its own");
    CHECK(initialised.count(name) == 0);
  }
}

TEST_CASE("A default RelocaliserParams is the pipeline config's", "[reloc][defaults]") {
  const sb::PipelineConfig c;
  const sb::RelocaliserParams p;
  CHECK(p.candidates == c.relocaliseCandidates);
  CHECK(p.confirmFrames == c.relocaliseConfirmFrames);
  CHECK(p.minPairAgreement == double(c.relocaliseMinPairAgreement));
  CHECK(p.agreementMargin == double(c.relocaliseAgreementMargin));
  CHECK(p.minConditioning == double(c.relocaliseMinConditioning));
  CHECK(p.maxMotionM == double(c.relocaliseMaxMotion));
  CHECK(p.maxRotationDeg == double(c.relocaliseMaxRotationDeg));
  CHECK(p.keyframeCapacity == size_t(c.keyframeCapacity));
  CHECK(p.keyframeMinDissimilarity == double(c.keyframeMinDissimilarity));
}
