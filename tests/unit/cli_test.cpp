// The command-line contract (README.md, "Commands"): exit statuses, messages that name the bad input,
// outputs written whole or not at all. Runs the real photoncl binary.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <new>
#include <stdexcept>

#include "core/error.h"
#include "geometry/scene_geometry.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "reference/light_tracer.h"
#include "run_photoncl.h"
#include "scene/load_scene.h"

namespace fs = std::filesystem;

namespace {

using photoncl_cli::Result;
using photoncl_cli::run;

std::string scene(const std::string& name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl_cli_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    size_t filesIn() const {
        size_t n = 0;
        for (auto& e : fs::directory_iterator(dir)) (void)e, ++n;
        return n;
    }
    fs::path dir;
};

TEST_F(CliTest, HelpListsEverySubcommandAndExitsZero) {
    Result r = run("--help");
    EXPECT_EQ(r.status, 0);
    for (const char* sub : {"devices", "render", "check", "compare"})
        EXPECT_NE(r.output.find(sub), std::string::npos) << sub;
    for (const char* sub : {"devices", "render", "check", "compare"}) {
        Result h = run(std::string(sub) + " --help");
        EXPECT_EQ(h.status, 0) << sub;
        EXPECT_NE(h.output.find("Usage"), std::string::npos) << sub;
    }
}

TEST_F(CliTest, UnknownOptionAndMissingArgumentAreBadInput) {
    EXPECT_EQ(run("render").status, 2);
    EXPECT_EQ(run("render " + scene("cornell-box.json") + " --no-such-option").status, 2);
    EXPECT_EQ(run("render " + scene("cornell-box.json") + " --passes -3").status, 2);
    EXPECT_EQ(run("frobnicate").status, 2);
}

TEST_F(CliTest, MissingSceneNamesTheFileAndWritesNothing) {
    fs::path out = dir / "out.exr";
    Result r = run("render " + (dir / "nope.json").string() + " -o " + out.string());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("nope.json"), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(), 0u);
}

TEST_F(CliTest, BadSceneNamesTheFieldAndWritesNothing) {
    fs::path bad = dir / "bad.json";
    {
        std::ifstream in(scene("cornell-box.json"));
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        size_t at = text.find("\"rho_d\"");
        ASSERT_NE(at, std::string::npos);
        size_t open = text.find('[', at), close = text.find(']', at);
        text.replace(open, close - open + 1, "[1.2, 0, 0]");
        std::ofstream(bad) << text;
    }
    Result r = run("render " + bad.string() + " -o " + (dir / "out.exr").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("bad.json"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rho_d"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1.2"), std::string::npos) << r.output;
    EXPECT_EQ(filesIn(), 1u);  // only bad.json
}

TEST_F(CliTest, RenderWritesExrWithMetadataAndPngAndNoStrayFiles) {
    fs::path out = dir / "cb.exr";
    Result r = run("render " + scene("cornell-box.json") + " -o " + out.string() +
                   " --method path --width 32 --height 32 --passes 2 --seed 7 -q");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_TRUE(fs::exists(dir / "cb.png"));
    EXPECT_EQ(filesIn(), 2u);  // no temporary files left behind
    pcl::ImageMetadata meta;
    pcl::Image img = pcl::readImage(out.string(), &meta);
    EXPECT_EQ(img.width, 32);
    EXPECT_EQ(img.height, 32);
    EXPECT_EQ(meta.method, "path");
    EXPECT_EQ(meta.samples, 2);
    EXPECT_EQ(meta.seed, 7u);
    double sum = 0;
    for (float v : img.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0);
}

TEST_F(CliTest, SameSeedGivesTheSameBitsAndCompareSaysSo) {
    std::string common = " --method path --width 24 --height 24 --passes 2 --seed 3 -q --no-png";
    ASSERT_EQ(run("render " + scene("cornell-box.json") + " -o " + (dir / "a.exr").string() + common).status, 0);
    ASSERT_EQ(run("render " + scene("cornell-box.json") + " -o " + (dir / "b.exr").string() + common).status, 0);
    pcl::Image a = pcl::readImage((dir / "a.exr").string()), b = pcl::readImage((dir / "b.exr").string());
    EXPECT_EQ(a.rgb, b.rgb);
    Result same = run("compare " + (dir / "a.exr").string() + " " + (dir / "b.exr").string() + " --max-rmse 0");
    EXPECT_EQ(same.status, 0) << same.output;
    EXPECT_NE(same.output.find("RMSE 0"), std::string::npos) << same.output;

    ASSERT_EQ(run("render " + scene("cornell-box.json") + " -o " + (dir / "c.exr").string() +
                  " --method path --width 24 --height 24 --passes 2 --seed 4 -q --no-png")
                  .status,
              0);
    Result differ = run("compare " + (dir / "c.exr").string() + " " + (dir / "a.exr").string() + " --max-rmse 1e-9");
    EXPECT_EQ(differ.status, 1) << differ.output;
}

// Sizes: A at n times B's size is box-averaged to B's pixels (a 256² render against a 64-px
// reference); any other mismatch, B larger than A included, is refused.
TEST_F(CliTest, CompareAveragesMultiplesAndRefusesOtherSizesAndMissingFiles) {
    ASSERT_EQ(run("render " + scene("cornell-box.json") + " -o " + (dir / "a.exr").string() +
                  " --method path --width 16 --height 16 --passes 1 -q --no-png")
                  .status,
              0);
    ASSERT_EQ(run("render " + scene("cornell-box.json") + " -o " + (dir / "b.exr").string() +
                  " --method path --width 12 --height 12 --passes 1 -q --no-png")
                  .status,
              0);
    EXPECT_EQ(run("compare " + (dir / "a.exr").string() + " " + (dir / "b.exr").string()).status, 2);
    EXPECT_EQ(run("compare " + (dir / "b.exr").string() + " " + (dir / "a.exr").string()).status, 2);

    const pcl::Image a = pcl::readImage((dir / "a.exr").string());
    pcl::writeLinearImage((dir / "half.exr").string(), pcl::boxDownsample(a, 2), pcl::ImageMetadata{});
    Result averaged =
        run("compare " + (dir / "a.exr").string() + " " + (dir / "half.exr").string() + " --max-rmse 1e-6");
    EXPECT_EQ(averaged.status, 0) << averaged.output;
    EXPECT_NE(averaged.output.find("box-averaged 2x2"), std::string::npos) << averaged.output;
    pcl::Image shifted = pcl::boxDownsample(a, 2);
    for (float& v : shifted.rgb) v *= 1.01f;
    pcl::writeLinearImage((dir / "shifted.exr").string(), shifted, pcl::ImageMetadata{});
    Result differ = run("compare " + (dir / "a.exr").string() + " " + (dir / "shifted.exr").string());
    EXPECT_NE(differ.output.find("mean ratio 0.99"), std::string::npos) << differ.output;
    Result missing = run("compare " + (dir / "a.exr").string() + " " + (dir / "zzz.exr").string());
    EXPECT_EQ(missing.status, 2);
    EXPECT_NE(missing.output.find("zzz.exr"), std::string::npos) << missing.output;
}

// --skip-specular-pixels SCENE: a change confined to the pixels that see the mirror or glass ball
// first vanishes from the figures, a change in one other pixel does not; a bad scene is bad input.
TEST_F(CliTest, CompareCanSkipThePixelsThatSeeMirrorsOrGlassFirst) {
    const std::string a = (dir / "a.exr").string(), balls = (dir / "balls.exr").string(),
                      wall = (dir / "wall.exr").string(), sc = scene("cornell-spheres-point.json");
    ASSERT_EQ(run("render " + sc + " -o " + a + " --method path --width 32 --height 32 --passes 1 -q --no-png").status,
              0);
    pcl::Scene s = pcl::loadScene(sc);
    s.camera.width = s.camera.height = 32;
    const std::vector<uint8_t> keep = pcl::pixelsSeeingNoDeltaSurfaceFirst(s, pcl::SceneGeometry::build(s));
    const pcl::Image img = pcl::readImage(a);
    pcl::Image changedBalls = img, changedWall = img;
    size_t left = 0;
    for (size_t i = 0; i < keep.size(); ++i)
        if (!keep[i]) changedBalls.rgb[3 * i] += 1.0f, ++left;
    ASSERT_GT(left, 20u);
    changedWall.rgb[0] += 1.0f;  // the top left pixel sees the ceiling
    ASSERT_TRUE(keep[0]);
    pcl::writeLinearImage(balls, changedBalls, pcl::ImageMetadata{});
    pcl::writeLinearImage(wall, changedWall, pcl::ImageMetadata{});
    EXPECT_EQ(run("compare " + balls + " " + a + " --max-rmse 1e-6").status, 1);
    Result masked = run("compare " + balls + " " + a + " --skip-specular-pixels " + sc + " --max-rmse 1e-6");
    EXPECT_EQ(masked.status, 0) << masked.output;
    EXPECT_NE(masked.output.find(std::to_string(left) + " pixels that see mirrors or glass first left out"),
              std::string::npos)
        << masked.output;
    EXPECT_EQ(run("compare " + wall + " " + a + " --skip-specular-pixels " + sc + " --max-rmse 1e-6").status, 1);
    Result bad = run("compare " + wall + " " + a + " --skip-specular-pixels " + (dir / "none.json").string());
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("none.json"), std::string::npos) << bad.output;
}

TEST_F(CliTest, UnknownDeviceIsADeviceFailureThatListsDevices) {
    Result r = run("check " + scene("cornell-box.json") + " --device no-such-device-xyz --rays 100");
    EXPECT_EQ(r.status, 3) << r.output;
    EXPECT_NE(r.output.find("no-such-device-xyz"), std::string::npos) << r.output;
}

// main.cpp maps the exception that ended a command through exitReportFor: bad input (what the
// user supplied) 2, everything else 3 (internal: a device failure or a broken contract, a bug),
// never 1, which says a check ran and failed. The binary's own statuses are tested around it:
// 2 for bad input, 1 for a failed comparison, 3 for an unknown device.
TEST(ExitStatus, EachKindOfErrorHasItsStatusAndPrefix) {
    const pcl::ExitReport input =
        pcl::exitReportFor(pcl::InputError("scene.json: camera.fov: expected (0, 180), got 0"));
    EXPECT_EQ(input.status, 2);
    EXPECT_EQ(input.message, "scene.json: camera.fov: expected (0, 180), got 0");
    const pcl::ExitReport device = pcl::exitReportFor(pcl::DeviceError("emit: CL_OUT_OF_RESOURCES"));
    EXPECT_EQ(device.status, 3);
    EXPECT_EQ(device.message, "device error: emit: CL_OUT_OF_RESOURCES");
    const pcl::ExitReport internal = pcl::exitReportFor(pcl::InternalError("eye paths: maxDepth 0: expected 1..64"));
    EXPECT_EQ(internal.status, 3);
    EXPECT_EQ(internal.message, "internal error: eye paths: maxDepth 0: expected 1..64");
    EXPECT_EQ(pcl::exitReportFor(std::runtime_error("x")).status, 3);
    EXPECT_EQ(pcl::exitReportFor(std::bad_alloc()).status, 3);
    EXPECT_EQ(pcl::kExitCheckFailed, 1);
}

TEST_F(CliTest, HelpDocumentsTheExitStatuses) {
    Result r = run("--help");
    EXPECT_EQ(r.status, 0);
    for (const char* s : {"0 success", "1 a check or comparison failed", "2 bad input", "3 internal error", "130"})
        EXPECT_NE(r.output.find(s), std::string::npos) << s << " missing from: " << r.output;
}

TEST_F(CliTest, CheckTraceOnAShippedScenePasses) {
    Result r = run("check " + scene("cornell-spheres.json") + " --device cpu --stage trace --rays 3000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("stage trace: PASSED"), std::string::npos) << r.output;
}

TEST_F(CliTest, WidthAloneKeepsTheCameraAspectRatio) {
    fs::path out = dir / "md.exr";
    ASSERT_EQ(run("render " + scene("motion-dof.json") + " -o " + out.string() +
                  " --method path --width 32 --passes 1 -q --no-png")
                  .status,
              0);
    pcl::Image img = pcl::readImage(out.string());
    EXPECT_EQ(img.width, 32);
    EXPECT_EQ(img.height, 24);  // motion-dof is 4:3
}

TEST_F(CliTest, RenderLogsThePlan) {
    Result r = run("render " + scene("cornell-spheres.json") + " -o " + (dir / "cs.exr").string() +
                   " --width 16 --height 16 --passes 1 --no-png");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("caustic map"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("LS+DE"), std::string::npos) << r.output;
}

// A sky-lit scene (environment light, no other): every stage runs and passes, and the photon
// methods render it.
TEST_F(CliTest, CheckAllPassesUnderASky) {
    Result r = run("check " + scene("sky-spheres.json") + " --device cpu --stage all --photons 4000 --rays 5000");
    EXPECT_EQ(r.status, 0) << r.output;
    for (const char* stage : {"emit", "trace_photons", "pass", "eye_paths", "direct_light", "render"})
        EXPECT_NE(r.output.find(std::string("stage ") + stage + ": PASSED"), std::string::npos) << stage << r.output;
    for (const char* method : {"fg", "direct", "progressive"}) {
        Result m = run("render " + scene("sky-spheres.json") + " -o " + (dir / "sky.exr").string() +
                       " --width 16 --height 12 --passes 1 --no-png --method " + method);
        EXPECT_EQ(m.status, 0) << method << m.output;
    }
}

// The textured asset under its image sky (scenes/courtyard/): every kernel stage against its twin
// with textures and the sky's aimed caustic photons at once.
TEST_F(CliTest, CheckAllPassesOnTheTexturedCourtyard) {
    Result r =
        run("check " + scene("courtyard/courtyard.json") + " --device cpu --stage all --photons 4000 --rays 5000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("FAILED"), std::string::npos) << r.output;
    for (const char* stage : {"emit", "trace_photons", "pass", "eye_paths", "direct_light", "render"})
        EXPECT_NE(r.output.find(std::string("stage ") + stage + ": PASSED"), std::string::npos) << stage << r.output;
}

TEST_F(CliTest, CheckPhotonStagesPassOnAShippedScene) {
    for (const char* stage :
         {"emit", "trace_photons", "deposit", "pass", "sort", "build", "knn", "estimate", "render"}) {
        Result r =
            run("check " + scene("cornell-spheres-point.json") + " --device cpu --stage " + stage + " --photons 4000");
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find(std::string("stage ") + stage + ": PASSED"), std::string::npos) << r.output;
    }
    EXPECT_EQ(run("check " + scene("cornell-box.json") + " --stage nonsense").status, 2);
    // The estimate stage also checks the precomputed irradiance lookup.
    Result r = run("check " + scene("cornell-spheres-point.json") + " --device cpu --stage estimate --photons 4000");
    EXPECT_NE(r.output.find("stage estimate (precomputed irradiance): PASSED"), std::string::npos) << r.output;
}

// check --stage all on a scene with media runs the stages that read media (every one passes) and
// names the ones it leaves out.
TEST_F(CliTest, CheckAllOnAMediaSceneRunsTheMediaStages) {
    Result r = run("check " + scene("media/cornell-fog.json") + " --device cpu --stage all --photons 4000");
    EXPECT_EQ(r.status, 0) << r.output;
    for (const char* stage :
         {"trace", "emit", "trace_photons", "deposit", "pass", "eye_paths", "direct_light", "volume_estimate"})
        EXPECT_NE(r.output.find(std::string("stage ") + stage + ": PASSED"), std::string::npos) << stage << r.output;
    EXPECT_NE(r.output.find("stages left out (the scene has participating media, which they do not read yet): sort, "
                            "build, knn, estimate, connect_caustics, render"),
              std::string::npos)
        << r.output;
}

// A scene with media renders progressive when --method is not given (fg's gather rays do not
// carry media yet: --method fg exits 2 with the reason); progressive renders it, finite.
TEST_F(CliTest, RenderPicksProgressiveForMediaAndFgRefusesThem) {
    const std::string out = (dir / "fog.exr").string();
    Result r = run("render " + scene("media/cornell-fog.json") +
                   " --width 16 --passes 1 --global-photons 5000 --caustic-photons 5000 -o " + out);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("method progressive: the scene has participating media"), std::string::npos) << r.output;
    r = run("render " + scene("media/cornell-fog.json") + " --method fg --width 16 --passes 1 -o " + out);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--method fg (fg's gather rays do not carry media yet)"), std::string::npos) << r.output;
    // auto: its pilot weighs fg, so media go to progressive, said so.
    r = run("render " + scene("media/cornell-fog.json") +
            " --method auto --width 16 --time 1 --global-photons 5000 --caustic-photons 5000 -o " + out);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("method auto: progressive: the scene has participating media"), std::string::npos)
        << r.output;
}

// volume_estimate reads the volume maps of a scene with media (and passes there); it refuses a
// scene without a medium (exit 2), and the other eye-pass stages still refuse media.
TEST_F(CliTest, CheckVolumeEstimateAcceptsMediaOnly) {
    Result r = run("check " + scene("media/cornell-fog.json") + " --device cpu --stage volume_estimate --photons 4000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("stage volume_estimate: PASSED"), std::string::npos) << r.output;
    r = run("check " + scene("cornell-box.json") + " --device cpu --stage volume_estimate");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("expected a scene with a participating medium"), std::string::npos) << r.output;
    EXPECT_EQ(run("check " + scene("media/cornell-fog.json") + " --device cpu --stage estimate").status, 2);
}

}  // namespace
