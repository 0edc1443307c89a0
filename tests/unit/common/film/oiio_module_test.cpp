// The OpenImageIO module (oiio_images.h): it loads and speaks this build's interface, and
// whatever else sits where a module is expected (nothing, a text file, a library without the
// table) is a clear error naming the path, never a crash.
#include "common/film/oiio_images.h"

#include <dlfcn.h>
#include <zlib.h>

#include <fstream>

#include <gtest/gtest.h>

#include "tests/support/test_env.h"

namespace pathfarm::oiio_module_test {
namespace {

TEST(OiioModule, LoadsWithThisBuildsInterface) {
    const auto images = oiio_images();
    ASSERT_TRUE(images.ok()) << images.error().message;
    EXPECT_EQ((*images)->abi, kOiioImagesAbi);
    const auto png = (*images)->encode_png(2, 1, {255, 0, 0, 0, 255, 0});
    ASSERT_TRUE(png.ok()) << png.error().message;
    EXPECT_GT(png->size(), 8u);
}

void expect_error_naming(const std::string& path, const char* problem) {
    const auto loaded = load_oiio_images(path);
    ASSERT_FALSE(loaded.ok()) << path;
    EXPECT_NE(loaded.error().message.find(path), std::string::npos) << loaded.error().message;
    EXPECT_NE(loaded.error().message.find(problem), std::string::npos) << loaded.error().message;
    EXPECT_EQ(loaded.error().message.find('\n'), std::string::npos) << loaded.error().message;
}

TEST(OiioModule, WhatIsNotAModuleIsAClearError) {
    const std::string dir = test::scratch_dir();
    expect_error_naming(dir + "/no-such-module.so", "cannot load");
    std::ofstream(dir + "/text.so") << "not a shared object\n";
    expect_error_naming(dir + "/text.so", "cannot load");
    // A real shared library without the table: zlib, which this test links.
    Dl_info info{};
    ASSERT_NE(dladdr(reinterpret_cast<void*>(&zlibVersion), &info), 0);
    expect_error_naming(info.dli_fname, "not an image I/O module");
}

}  // namespace
}  // namespace pathfarm::oiio_module_test
