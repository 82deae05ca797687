#pragma once
// Helpers for tests: where the shared real data is, and scratch directories.

#include <string>

namespace sb::test {

// ../shared/data beside the checkout (overridable with SB_SHARED_DATA for running tests elsewhere).
std::string sharedDataDir();

// True when the shared data directory exists and holds the named subdirectory.
bool hasSharedData(const std::string& sub = "");

// The binary a system test runs: `built` (the build's), or the path in the environment variable `env` when it
// is set and not empty, to run a test against another build (e.g. SB_TEST_SLAMBOOSTERD=old/slamboosterd, to
// show that a test fails before a fix).
std::string testBinary(const char* env, const std::string& built);

// A fresh, empty directory under the build tree for one test's outputs.
std::string scratchDir(const std::string& name);

}  // namespace sb::test
