#pragma once
// Helpers for tests: where the shared real data is, and scratch directories.

#include <string>

namespace sb::test {

// ../shared/data beside the checkout (overridable with SB_SHARED_DATA for running tests elsewhere).
std::string sharedDataDir();

// True when the shared data directory exists and holds the named subdirectory.
bool hasSharedData(const std::string& sub = "");

// A fresh, empty directory under the build tree for one test's outputs.
std::string scratchDir(const std::string& name);

}  // namespace sb::test
