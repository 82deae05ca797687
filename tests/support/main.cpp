// Test main: Catch2 v2. Tests that read ../shared/data carry the tag [data] and are registered as their own
// CTest entry. When the data is missing, that entry is reported as skipped (exit 77) with the reason, except
// when CI is set, where missing data is a failure.

#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include "tests/support/test_data.h"

int main(int argc, char** argv) {
  bool wantsData = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strstr(argv[i], "[data]") && !std::strstr(argv[i], "~[data]")) wantsData = true;
  }
  if (wantsData && !sb::test::hasSharedData()) {
    const bool ci = std::getenv("CI") != nullptr;
    std::cerr << (ci ? "FAILED" : "SKIPPED") << ": shared data not found at '" << sb::test::sharedDataDir()
              << "' (place ../shared/data beside the checkout or set SB_SHARED_DATA)"
              << (ci ? "; CI is set, so missing data is a failure" : "") << "\n";
    return ci ? 1 : 77;
  }
  return Catch::Session().run(argc, argv);
}
