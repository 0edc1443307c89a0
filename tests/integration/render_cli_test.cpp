// pathfarm-render as a user runs it: an image without NaN/Inf, the summary line, and a clear
// one-line error (exit 2 for usage, 1 for runtime) on bad input.
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/film/image_io.h"
#include "tests/support/test_env.h"

namespace pathfarm {
namespace {

struct CliRun {
    int exit_code;
    std::string output;
};

CliRun run_cli(const std::string& args, const char* exe = PATHFARM_RENDER_EXE) {
    const std::string cmd = std::string(exe) + " " + args + " 2>&1";
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

double printed_relative_mse(const std::string& output) {
    const std::size_t at = output.find("rel_mse=");
    return at == std::string::npos ? -1.0 : std::stod(output.substr(at + 8));
}

// --denoise: the same linear output format, the filtered image, much closer to the reference.
TEST(RenderCli, DenoiseWritesTheFilteredLinearImage) {
    const std::string dir = test::scratch_dir();
    const std::string size = "--scene builtin:cornell --width 48 --height 48 ";
    ASSERT_EQ(run_cli(size + "--spp 1024 --seed 9 --out " + dir + "/ref.pfm").exit_code, 0);
    const CliRun plain =
        run_cli(size + "--spp 2 --reference " + dir + "/ref.pfm --out " + dir + "/plain.pfm");
    const CliRun denoised = run_cli(size + "--spp 2 --denoise --reference " + dir +
                                    "/ref.pfm --out " + dir + "/denoised.pfm");
    ASSERT_EQ(plain.exit_code, 0) << plain.output;
    ASSERT_EQ(denoised.exit_code, 0) << denoised.output;
    EXPECT_NE(denoised.output.find("denoised in"), std::string::npos) << denoised.output;
    const double before = printed_relative_mse(plain.output),
                 after = printed_relative_mse(denoised.output);
    ASSERT_GT(before, 0.0) << plain.output;
    ASSERT_GE(after, 0.0) << denoised.output;
    EXPECT_LT(after, 0.5 * before) << before << " -> " << after;
    auto img = read_image(dir + "/denoised.pfm");
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(count_nonfinite(*img), 0u);
    float brightest = 0.0f;  // linear radiance: the lamp is far above 1
    for (float v : img->rgb)
        brightest = std::max(brightest, v);
    EXPECT_GT(brightest, 2.0f);
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
    // --seconds 0 rendered the default 16 spp before instead of refusing the value, and inf
    // never finished.
    for (const std::string seconds : {"0", "-1", "nan", "inf"}) {
        const CliRun time = run_cli("--scene builtin:cornell --width 8 --height 8 --seconds " +
                                    seconds + " --out " + dir + "/x.pfm");
        EXPECT_EQ(time.exit_code, 2) << seconds << ": " << time.output;
        EXPECT_NE(time.output.find("--seconds "), std::string::npos) << time.output;
        EXPECT_EQ(time.output.find("samples_per_s="), std::string::npos) << time.output;
    }
    // Values that rendered silently before: a NaN pose, a black PNG, a camera check blaming
    // --up for a NaN point.
    for (const auto& [option, value] :
         std::vector<std::pair<std::string, std::string>>{{"--time", "nan"},
                                                          {"--exposure", "-1"},
                                                          {"--exposure", "nan"},
                                                          {"--look-from", "nan 0.3 0"},
                                                          {"--look-at", "0.3 inf 0"}}) {
        const std::string camera = option == "--look-from"
                                       ? " --look-at 0.3 0.1 0"
                                       : (option == "--look-at" ? " --look-from 0.3 0.3 0" : "");
        const CliRun bad = run_cli("--scene builtin:cornell --spp 1 --width 8 --height 8 " +
                                   option + " " + value + camera + " --out " + dir + "/x.png");
        EXPECT_EQ(bad.exit_code, 2) << option << " " << value << ": " << bad.output;
        EXPECT_NE(bad.output.find(option + " "), std::string::npos) << bad.output;
        EXPECT_NE(bad.output.find("must be"), std::string::npos) << bad.output;
    }
    // The --look-from camera's settings without it: ignored before, even a NaN field of view,
    // and the scene's own camera rendered.
    const CliRun camera = run_cli(
        "--scene builtin:cornell --spp 1 --width 8 --height 8 --camera -5 "
        "--out " +
        dir + "/x.pfm");
    EXPECT_EQ(camera.exit_code, 2) << camera.output;
    EXPECT_NE(camera.output.find("--camera -5: must be -1"), std::string::npos) << camera.output;
    for (const std::string option : {"--fov nan", "--fov 60", "--look-at 0 0 0", "--up 0 0 1"}) {
        const CliRun alone = run_cli("--scene builtin:cornell --spp 1 --width 8 --height 8 " +
                                     option + " --out " + dir + "/x.pfm");
        EXPECT_EQ(alone.exit_code, 2) << option << ": " << alone.output;
        EXPECT_NE(alone.output.find("requires --look-from"), std::string::npos) << alone.output;
        EXPECT_EQ(alone.output.find("samples_per_s="), std::string::npos) << alone.output;
    }
    // An up that cannot orient the view rendered a black image (a NaN camera) before.
    for (const std::string up : {"0 0 0", "0 1 0", "0 -3 0"}) {
        const CliRun view = run_cli(
            "--scene builtin:cornell --spp 1 --width 8 --height 8 "
            "--look-from 0.3 0.3 0 --look-at 0.3 0.1 0 --up " +
            up + " --out " + dir + "/x.pfm");
        EXPECT_EQ(view.exit_code, 2) << up << ": " << view.output;
        EXPECT_NE(view.output.find("--up " + up + ": zero or parallel to the view"),
                  std::string::npos)
            << view.output;
    }
}

// Without the OpenImageIO module (oiio_images.h) PFM still works and an EXR is a one-line
// error naming where the module was looked for, before any rendering.
TEST(RenderCli, AMissingImageModuleIsAClearErrorAndPfmNeedsNone) {
    const std::string dir = test::scratch_dir();
    const std::string env = "PATHFARM_OIIO_MODULE=" + dir + "/gone.so ";
    const std::string scene = "--scene builtin:cornell --spp 1 --width 8 --height 8 --out ";
    const CliRun pfm = run_cli(scene + dir + "/x.pfm", (env + PATHFARM_RENDER_EXE).c_str());
    EXPECT_EQ(pfm.exit_code, 0) << pfm.output;
    const CliRun exr = run_cli(scene + dir + "/x.exr", (env + PATHFARM_RENDER_EXE).c_str());
    EXPECT_EQ(exr.exit_code, 1) << exr.output;
    EXPECT_NE(exr.output.find("image I/O module libpathfarm_oiio.so not found (tried " + dir +
                              "/gone.so; set PATHFARM_OIIO_MODULE)"),
              std::string::npos)
        << exr.output;
    EXPECT_EQ(exr.output.find("samples_per_s="), std::string::npos) << exr.output;
}

// JPEG textures are decoded without the module (jpeg_codec.h): a glTF and an OBJ scene whose
// textures are all JPEG render with it gone, with no texture left out, and the same pixels. The
// barn lamp's KTX2 textures are dropped as before, without asking for the module.
TEST(RenderCli, JpegTexturedScenesNeedNoImageModule) {
    PF_REQUIRE_SCENES(scenes);
    const std::string dir = test::scratch_dir();
    const std::string env = "PATHFARM_OIIO_MODULE=" + dir + "/gone.so ";
    for (const char* scene : {"/cesium-man/CesiumMan.gltf", "/dabrovic-sponza/sponza.obj"}) {
        const std::string args =
            "--scene " + scenes + scene + " --spp 1 --width 24 --height 16 --out " + dir;
        const CliRun without = run_cli(args + "/without.pfm", (env + PATHFARM_RENDER_EXE).c_str());
        ASSERT_EQ(without.exit_code, 0) << scene << ": " << without.output;
        EXPECT_EQ(without.output.find("not loaded"), std::string::npos) << without.output;
        EXPECT_EQ(without.output.find("not decoded"), std::string::npos) << without.output;
        ASSERT_EQ(run_cli(args + "/with.pfm").exit_code, 0) << scene;
        auto a = read_image(dir + "/without.pfm"), b = read_image(dir + "/with.pfm");
        ASSERT_TRUE(a.ok() && b.ok()) << scene;
        EXPECT_EQ(a->rgb, b->rgb) << scene;
    }
    const CliRun lamp = run_cli("--scene " + scenes +
                                    "/anisotropy-barn-lamp/AnisotropyBarnLamp.gltf --spp 1 "
                                    "--width 16 --height 16 --out " +
                                    dir + "/lamp.pfm",
                                (env + PATHFARM_RENDER_EXE).c_str());
    ASSERT_EQ(lamp.exit_code, 0) << lamp.output;
    EXPECT_NE(lamp.output.find("a KTX2 image"), std::string::npos) << lamp.output;
    EXPECT_EQ(lamp.output.find("module"), std::string::npos) << lamp.output;
}

TEST(RenderCli, AnimatedSceneRendersAtTheRequestedTime) {
    PF_REQUIRE_SCENES(scenes);
    const std::string dir = test::scratch_dir();
    const std::string common =
        "--scene " + scenes +
        "/box-animated/BoxAnimated.gltf --spp 2 --width 32 --height 32 --out ";
    ASSERT_EQ(run_cli(common + dir + "/a.exr --time 0.2").exit_code, 0);
    ASSERT_EQ(run_cli(common + dir + "/b.exr --time 1.7 --clip 0").exit_code, 0);
    auto a = read_image(dir + "/a.exr"), b = read_image(dir + "/b.exr");
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_NE(a->rgb, b->rgb) << "the pose must change with --time";
    const CliRun bad = run_cli(common + dir + "/c.exr --time 1 --clip NoSuchClip");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.output.find("NoSuchClip"), std::string::npos);
}

TEST(CoordinatorCli, ExportsPoseAndRejectsBadInput) {
    PF_REQUIRE_SCENES(scenes);
    const std::string dir = test::scratch_dir();
    const CliRun ok =
        run_cli("--scene " + scenes + "/cesium-man/CesiumMan.gltf --export-at 0.5 --export " + dir +
                    "/man.obj",
                PATHFARM_COORDINATOR_EXE);
    EXPECT_EQ(ok.exit_code, 0) << ok.output;
    const CliRun missing =
        run_cli("--scene " + dir + "/none.glb --export-at 1 --export " + dir + "/x.obj",
                PATHFARM_COORDINATOR_EXE);
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_NE(missing.output.find("none.glb"), std::string::npos);
    EXPECT_EQ(run_cli("--export-at 1", PATHFARM_COORDINATOR_EXE).exit_code, 2);
    // An infinite game clock put every frame at time 0, offline and in the farm, silently.
    for (const std::string mode :
         {"--offline --frames 2", "--tracer-port 0 --insecure-plaintext"}) {
        // Under timeout: without the check the farm waits for tracers.
        const CliRun clock =
            run_cli("--scene builtin:cornell --width 16 --height 16 --fps inf " + mode,
                    ("PATHFARM_SECRET=0123456789abcdef0123456789abcdef timeout 30 " +
                     std::string(PATHFARM_COORDINATOR_EXE))
                        .c_str());
        EXPECT_EQ(clock.exit_code, 2) << mode << ": " << clock.output;
        EXPECT_NE(clock.output.find("--fps inf: must be finite"), std::string::npos)
            << clock.output;
    }
    // A negative bounce limit went to the tracers as it was.
    const CliRun depth = run_cli(
        "--scene builtin:cornell --max-depth -1 --tracer-port 0 "
        "--insecure-plaintext",
        ("PATHFARM_SECRET=0123456789abcdef0123456789abcdef timeout 30 " +
         std::string(PATHFARM_COORDINATOR_EXE))
            .c_str());
    EXPECT_EQ(depth.exit_code, 2) << depth.output;
    EXPECT_NE(depth.output.find("--max-depth -1: must be 0..1024"), std::string::npos)
        << depth.output;
    // Taken silently before: a NaN export time, a NaN rebuild factor (no BVH ever rebuilt), a
    // negative frame count (the default instead).
    for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
             {"--export-at nan --export " + dir + "/n.obj", "--export-at nan: must be finite"},
             {"--offline --frames 2 --rebuild-factor nan",
              "--rebuild-factor nan: must be finite and >= 1"},
             {"--offline --frames 2 --rebuild-factor 0.5",
              "--rebuild-factor 0.5: must be finite and >= 1"},
             {"--offline --frames -1", "--frames -1: must be >= 0"}}) {
        const CliRun bad = run_cli("--scene builtin:cornell " + args, PATHFARM_COORDINATOR_EXE);
        EXPECT_EQ(bad.exit_code, 2) << args << ": " << bad.output;
        EXPECT_NE(bad.output.find(message), std::string::npos) << args << ": " << bad.output;
        EXPECT_EQ(bad.output.find("replica_ok"), std::string::npos) << bad.output;
    }
}

// Values the proxy ran with before: a NaN fault interval (a fault every 50 ms), a negative
// bandwidth (wrapped to no cap) and its own port as the target (each connection it accepted
// opened another).
TEST(FaultProxyCli, BadInputIsAOneLineError) {
    for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
             {"--listen 1 --target 2 --random-faults nan",
              "--random-faults nan: must be in [0, 3600]"},
             {"--listen 1 --target 2 --bandwidth -5", "--bandwidth"},
             {"--listen 40917 --target 40917", "--target 40917: the proxy's own --listen port"}}) {
        // Under timeout: without the checks the proxy relays until stopped.
        const CliRun bad =
            run_cli(args, ("timeout 10 " + std::string(PATHFARM_FAULT_PROXY_EXE)).c_str());
        EXPECT_EQ(bad.exit_code, 2) << args << ": " << bad.output;
        EXPECT_NE(bad.output.find(message), std::string::npos) << args << ": " << bad.output;
    }
}

std::vector<std::vector<double>> read_csv(const std::string& path, std::string& header) {
    std::ifstream in(path);
    std::getline(in, header);
    std::vector<std::vector<double>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ','))
            row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

TEST(CoordinatorCli, OfflineLoopReplicatesEveryFrameOfASkinnedScene) {
    PF_REQUIRE_SCENES(scenes);
    const std::string csv = test::scratch_dir() + "/stats.csv";
    const CliRun run = run_cli(
        "--scene " + scenes + "/cesium-man/CesiumMan.gltf --offline --frames 20 --stats-csv " + csv,
        PATHFARM_COORDINATOR_EXE);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::string header;
    const auto rows = read_csv(csv, header);
    EXPECT_EQ(header, "frame,commit_bytes,animate_ms,accel_ms,commit_ms,dynamic_tris,replica_ok");
    ASSERT_EQ(rows.size(), 20u);
    for (std::size_t f = 1; f < rows.size(); ++f) {
        EXPECT_EQ(rows[f][6], 1.0) << "replica_ok, frame " << f;
        EXPECT_GT(rows[f][5], 0.0) << "the skinned mesh deforms every frame";
        EXPECT_GT(rows[f][1], 1000.0) << "deformed vertex data travels";
        EXPECT_LT(rows[f][1], rows[0][1] / 10) << "but far less than the snapshot";
    }
}

TEST(CoordinatorCli, StaticSceneCommitsAreTiny) {
    const std::string csv = test::scratch_dir() + "/stats.csv";
    const CliRun run = run_cli("--scene builtin:default --offline --frames 10 --stats-csv " + csv,
                               PATHFARM_COORDINATOR_EXE);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::string header;
    const auto rows = read_csv(csv, header);
    ASSERT_EQ(rows.size(), 10u);
    for (std::size_t f = 1; f < rows.size(); ++f)
        EXPECT_LE(rows[f][1], 64.0);
    EXPECT_EQ(
        run_cli("--scene builtin:default --offline --frames 0", PATHFARM_COORDINATOR_EXE).exit_code,
        2);
    EXPECT_EQ(run_cli("--scene builtin:default", PATHFARM_COORDINATOR_EXE).exit_code, 2);
}

}  // namespace
}  // namespace pathfarm
