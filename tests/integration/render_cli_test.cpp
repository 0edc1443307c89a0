// pathfarm-render as a user runs it: an image without NaN/Inf, the summary line, and a clear
// one-line error (exit 2 for usage, 1 for runtime) on bad input.
#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "common/film/image_io.h"
#include "tests/support/test_env.h"

namespace pathfarm {
namespace {

struct CliRun {
    int exit_code;
    std::string output;
};

CliRun run_cli(const std::string& args) {
    const std::string cmd = std::string(PATHFARM_RENDER_EXE) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe))
        out += buf.data();
    const int status = pclose(pipe);
    return {WEXITSTATUS(status), out};
}

TEST(RenderCli, RendersCornellWithoutNonFinitePixels) {
    const std::string out = test::scratch_dir() + "/c.exr";
    const CliRun r = run_cli("--scene builtin:cornell --spp 8 --width 48 --height 48 --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("samples_per_s="), std::string::npos);
    EXPECT_NE(r.output.find("rays_per_s="), std::string::npos);
    auto img = read_image(out);
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(count_nonfinite(*img), 0u);
    EXPECT_GT(img->pixel(24, 10).x, 0.0f);
}

TEST(RenderCli, BadInputGivesOneLineErrors) {
    const std::string dir = test::scratch_dir();
    const CliRun missing = run_cli("--scene " + dir + "/missing.gltf --out " + dir + "/x.exr");
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_NE(missing.output.find("missing.gltf: no such file"), std::string::npos)
        << missing.output;
    const CliRun size = run_cli("--scene builtin:cornell --width 0 --out " + dir + "/x.exr");
    EXPECT_EQ(size.exit_code, 2) << size.output;
    EXPECT_NE(size.output.find("--width"), std::string::npos);
    const CliRun flag = run_cli("--no-such-flag");
    EXPECT_EQ(flag.exit_code, 2);
    const CliRun ext =
        run_cli("--scene builtin:cornell --spp 1 --width 8 --height 8 --out " + dir + "/x.bmpx");
    EXPECT_EQ(ext.exit_code, 2) << ext.output;
    EXPECT_NE(run_cli("--help").output.find("--max-depth"), std::string::npos);
}

}  // namespace
}  // namespace pathfarm
