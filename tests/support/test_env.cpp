// Test environment helpers.
#include "tests/support/test_env.h"

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

namespace pathfarm::test {
namespace {

#ifdef PATHFARM_TEST_POCL_CACHE
// PoCL's kernel cache in the build tree: only the first test run after a kernel change compiles.
// Child processes (tracers started by farm tests) inherit it.
const bool kPoclCacheSet = [] {
    return setenv("POCL_CACHE_DIR", PATHFARM_TEST_POCL_CACHE, 0) == 0;
}();
#endif

}  // namespace

std::string scenes_dir_or_skip() {
    const char* dir = std::getenv("PATHFARM_SCENES");
    const bool present = dir != nullptr && std::filesystem::is_directory(dir);
    if (!present && std::getenv("CI") != nullptr) {
        ADD_FAILURE() << "PATHFARM_SCENES (" << (dir ? dir : "unset")
                      << ") is missing, and CI is set: scene tests must not be skipped";
        return {};
    }
    return present ? std::string(dir) : std::string();
}

std::string scratch_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto dir = std::filesystem::temp_directory_path() / "pathfarm-tests" /
                     (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

}  // namespace pathfarm::test
