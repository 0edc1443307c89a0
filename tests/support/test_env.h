// Test environment: where the shared scenes are (PATHFARM_SCENES) and scratch files.
#pragma once

#include <string>

namespace pathfarm::test {

// Folder of the shared scenes. When it is missing the calling test is skipped, or fails when
// the CI environment variable is set (CI must never silently skip scene tests).
std::string scenes_dir_or_skip();
#define PF_REQUIRE_SCENES(var)                                      \
    const std::string var = ::pathfarm::test::scenes_dir_or_skip(); \
    if (var.empty()) GTEST_SKIP() << "PATHFARM_SCENES not available"

// A fresh temporary directory for this test (removed at process exit is not required).
std::string scratch_dir();

}  // namespace pathfarm::test
