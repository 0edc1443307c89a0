// A farm of one Embree and one OpenCL tracer (real processes on loopback, PoCL): the OpenCL
// tracer asks for and traverses the coordinator's BVH, and the rows of the two backends are
// statistically indistinguishable, at their boundary and over the whole frame.
#include <cstdlib>
#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "common/film/image_io.h"
#include "tests/support/farm_harness.h"
#include "tests/support/process.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"

namespace pathfarm::mixed_farm_test {
namespace {

using test::Farm;

constexpr int kFrames = 16;
constexpr double kAlpha = 0.01;

FloatImage read(const std::string& path) {
    auto image = read_image(path);
    EXPECT_TRUE(image.ok()) << path << ": " << (image.ok() ? "" : image.error().message);
    return image.ok() ? *image : FloatImage{};
}

// Rows [y0, y1) of an image.
FloatImage crop_rows(const FloatImage& image, int y0, int y1) {
    FloatImage out(image.width, y1 - y0);
    for (int y = y0; y < y1; ++y)
        std::copy(image.row(y), image.row(y) + 3 * image.width, out.row(y - y0));
    return out;
}

// Embree-only renders of other frame numbers: the same distribution, independent numbers.
std::string independent_reference(Farm& farm, int frame) {
    const std::string out = farm.dir + "/independent_" + std::to_string(frame) + ".pfm";
    test::Process render({test::kRender, "--scene", farm.scene, "--width", "64", "--height", "50",
                          "--spp", std::to_string(farm.spp), "--frame", std::to_string(frame),
                          "--out", out, "--log-level", "error"},
                         farm.dir + "/independent.log");
    EXPECT_EQ(render.wait(std::chrono::seconds(30)), std::optional<int>(0));
    return out;
}

TEST(MixedFarm, EmbreeAndOpenClRowsAreIndistinguishable) {
    Farm farm;
    farm.spp = 4;
    farm.start({"--frames", std::to_string(kFrames), "--min-tracers", "2"});
    farm.add_tracer("embree", {"--max-reconnects", "0", "--backend", "embree"});
    farm.add_tracer("opencl",
                    {"--max-reconnects", "0", "--backend", "opencl", "--log-level", "debug"});
    ASSERT_EQ(farm.finish(std::chrono::seconds(120)), 0);

    // The OpenCL tracer's first assignment per frame (an idle tracer may then take rows from the
    // other: the CSV records the first assignment and how many rows were delivered).
    std::map<int, std::pair<int, int>> opencl_rows;  // frame -> [first, end)
    for (const auto& row : farm.csv("tracers.csv")) {
        ASSERT_GE(row.size(), 6u);
        if (row[1] != "opencl") continue;
        const int first = std::stoi(row[2]);
        opencl_rows[std::stoi(row[0])] = {first, first + std::stoi(row[3])};
        EXPECT_GT(std::stoi(row[5]), 0) << "the OpenCL tracer delivers rows of frame " << row[0];
    }
    ASSERT_EQ(opencl_rows.size(), std::size_t(kFrames)) << "the OpenCL tracer renders every frame";

    std::vector<FloatImage> band_farm, band_independent, whole_farm, whole_independent;
    int opencl_rendered_rows = 0;
    for (int f = 0; f < kFrames; ++f) {
        const FloatImage farm_frame = read(farm.frame(f));
        const FloatImage same_numbers = read(farm.reference(f));
        const auto [y0, y1] = opencl_rows.at(f);
        // Embree's rows are pathfarm-render's bit for bit; OpenCL's draw the same random
        // numbers, so nearly every value matches too. A row is one or the other.
        for (int y = 0; y < 50; ++y) {
            std::size_t identical = 0, close = 0;
            for (int i = 0; i < 3 * 64; ++i) {
                const float a = farm_frame.row(y)[i], b = same_numbers.row(y)[i];
                identical += a == b;
                close += std::abs(a - b) <= 1e-4f * (1.0f + std::abs(b));
            }
            if (identical < 3 * 64) {
                ++opencl_rendered_rows;
                EXPECT_GT(close, std::size_t(0.9 * 3 * 64)) << "row " << y << " of frame " << f;
            }
        }

        // The four rows each side of the boundary between the two backends.
        const int boundary = y0 > 0 ? y0 : y1;
        const int b0 = std::clamp(boundary - 4, 0, 50 - 8);
        const FloatImage independent = read(independent_reference(farm, kFrames + f));
        band_farm.push_back(crop_rows(farm_frame, b0, b0 + 8));
        band_independent.push_back(crop_rows(independent, b0, b0 + 8));
        whole_farm.push_back(farm_frame);
        whole_independent.push_back(independent);
    }
    EXPECT_GT(opencl_rendered_rows, 5 * kFrames) << "rows that only OpenCL can have rendered";
    const auto band = test::compare_batches(band_farm, band_independent, kAlpha, 2);
    EXPECT_TRUE(band.agree(kAlpha))
        << "boundary band: min pixel p " << band.min_pixel_p << " (threshold "
        << band.pixel_threshold << "), mean p " << band.mean_p;
    const auto whole = test::compare_batches(whole_farm, whole_independent, kAlpha, 2);
    EXPECT_TRUE(whole.agree(kAlpha))
        << "whole frame: min pixel p " << whole.min_pixel_p << " (threshold "
        << whole.pixel_threshold << "), mean p " << whole.mean_p;

    // The OpenCL tracer traversed the coordinator's BVH: it built none of its own.
    const std::string log = test::read_file(farm.dir + "/opencl.log");
    EXPECT_NE(log.find("0 meshes with the tracer's own BVH"), std::string::npos) << log;
}

TEST(MixedFarm, RunsTheRealTimeDemo) {
    // The demo's mode (paced, scaled, converging, the scene's game) with both backends.
    Farm farm;
    farm.mode = {"--target-fps", "10"};
    farm.start({"--frames", "20", "--min-tracers", "2"});
    farm.add_tracer("embree", {"--max-reconnects", "0", "--backend", "embree"});
    farm.add_tracer("opencl", {"--max-reconnects", "0", "--backend", "opencl"});
    ASSERT_EQ(farm.finish(std::chrono::seconds(120)), 0);
    int opencl_frames = 0;
    for (const auto& row : farm.csv("tracers.csv"))
        opencl_frames += row.size() >= 4 && row[1] == "opencl" && std::stoi(row[3]) > 0;
    EXPECT_GE(opencl_frames, 15) << test::read_file(farm.dir + "/coordinator.log");
    for (int f : {5, 19}) {
        const FloatImage frame = read(farm.frame(f));
        ASSERT_FALSE(frame.rgb.empty());
        for (float v : frame.rgb)
            ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(OpenClCli, NoPlatformIsAOneLineRefusal) {
    // An ICD loader that finds no vendor: what a machine without an OpenCL driver sees.
    const std::string dir = test::scratch_dir();
    std::filesystem::create_directories(dir + "/no-vendors");
    setenv("OCL_ICD_VENDORS", (dir + "/no-vendors").c_str(), 1);
    test::Process render({test::kRender, "--scene", "builtin:cornell", "--width", "8", "--height",
                          "8", "--backend", "opencl", "--out", dir + "/x.pfm"},
                         dir + "/render.log");
    const auto rc = render.wait(std::chrono::seconds(30));
    unsetenv("OCL_ICD_VENDORS");
    EXPECT_EQ(rc, std::optional<int>(1));
    const std::string log = test::read_file(dir + "/render.log");
    EXPECT_NE(log.find("pathfarm-render: opencl backend: no OpenCL platform found"),
              std::string::npos)
        << log;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.pfm"));
}

}  // namespace
}  // namespace pathfarm::mixed_farm_test
