// Media in the plan and on the command line: `analyze` reports volume paths
// L(S|D|V)*V(S|D|V)*E and plans a volume map only when a medium in use scatters; the photon
// methods refuse a scene with media (exit 2, saying that --method path renders them), and
// --method path renders it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "prep/prepared_scene.h"
#include "run_photoncl.h"
#include "scene/load_scene.h"

using namespace pcl;
namespace fs = std::filesystem;

namespace {

// A floor lit by a point light in fog (the global medium); `fog` replaces the medium's entry.
std::string foggyScene(
    const std::string& fog = R"({"name": "fog", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.2, 0.2, 0.2]})") {
    return R"({"camera": {"position": [0, 0.5, 5], "look_at": [0, 0.5, 0], "fov": 40, "resolution": [8, 8]},
 "materials": [{"name": "white", "rho_d": [0.5, 0.5, 0.5]}],
 "media": [)" +
           fog + R"(],
 "medium": "fog",
 "shapes": [{"type": "quad", "material": "white", "corner": [-5, 0, -5], "edge_u": [0, 0, 10], "edge_v": [10, 0, 0]}],
 "lights": [{"type": "point", "position": [0, 3, 0], "power": [100, 100, 100]}]})";
}

std::string writeScene(const std::string& name, const std::string& text) {
    fs::path p = fs::temp_directory_path() / ("photoncl-volume-plan-" + std::to_string(::getpid()) + "-" + name);
    std::ofstream(p) << text;
    return p.string();
}

}  // namespace

TEST(VolumePlan, ScatteringMediumPlansAVolumeMap) {
    const std::string path = writeScene("fog.json", foggyScene());
    Scene s = loadScene(path);
    PreparedScene a = prepareScene(s);
    EXPECT_TRUE(a.paths.volume);
    EXPECT_EQ(a.paths.media, 1u);
    EXPECT_EQ(a.paths.scatteringMedia, 1u);
    EXPECT_TRUE(a.plan.volumeMap);
    EXPECT_EQ(a.plan.volumePhotons, PlanSettings{}.globalPhotons);  // the global pass stores them
    ASSERT_EQ(a.plan.reasons.size(), 8u);
    EXPECT_NE(a.plan.reasons[7].find("light scatters in media"), std::string::npos) << a.plan.reasons[7];
    const std::string text = formatPlan(s, a.paths, a.plan);
    EXPECT_NE(text.find("L(S|D|V)*V(S|D|V)*E yes"), std::string::npos) << text;
    EXPECT_NE(text.find("scattering media: fog (global)"), std::string::npos) << text;
    EXPECT_NE(text.find("volume map           yes, 200000 photons"), std::string::npos) << text;
    fs::remove(path);
}

TEST(VolumePlan, NoVolumeMapWithoutScattering) {
    const std::string path = writeScene("smoke.json", foggyScene(R"({"name": "fog", "sigma_a": [0.3, 0.2, 0.1]})"));
    Scene s = loadScene(path);
    PreparedScene a = prepareScene(s);
    EXPECT_FALSE(a.paths.volume);
    EXPECT_EQ(a.paths.media, 1u);
    EXPECT_FALSE(a.plan.volumeMap);
    EXPECT_EQ(a.plan.volumePhotons, 0u);
    EXPECT_EQ(a.plan.reasons[7], "media absorb only: no scattering events to store photons at");
    fs::remove(path);

    Scene plain = loadScene(std::string(PHOTONCL_SOURCE_DIR) + "/scenes/cornell-box.json");
    PreparedScene b = prepareScene(plain);
    EXPECT_FALSE(b.paths.volume);
    EXPECT_FALSE(b.plan.volumeMap);
    EXPECT_EQ(b.plan.reasons[7], "no participating media");
}

// fg refuses media with the reason; direct, progressive and the path tracer render them (and
// auto, whose pilot weighs fg, renders progressive: cli_test.cpp). (Sweeps of media scenes:
// sweep_cli_test.cpp.)
TEST(VolumePlan, FgRefusesMediaAndTheOtherMethodsRenderThem) {
    const std::string path = writeScene("cli.json", foggyScene());
    const std::string out =
        (fs::temp_directory_path() / ("photoncl-volume-plan-" + std::to_string(::getpid()) + ".exr")).string();
    photoncl_cli::Result analyze = photoncl_cli::run("analyze " + path);
    EXPECT_EQ(analyze.status, 0) << analyze.output;
    EXPECT_NE(analyze.output.find("volume map           yes"), std::string::npos) << analyze.output;
    {
        photoncl_cli::Result r = photoncl_cli::run("render " + path + " -o " + out + " --method fg");
        EXPECT_EQ(r.status, 2) << r.output;
        EXPECT_NE(r.output.find("medium: expected a scene without participating media for --method fg (fg's gather "
                                "rays do not carry media yet)"),
                  std::string::npos)
            << r.output;
        EXPECT_FALSE(fs::exists(out));
    }
    for (const char* method : {"direct", "progressive"}) {
        photoncl_cli::Result r = photoncl_cli::run("render " + path + " -o " + out + " --method " + method +
                                                   " --width 16 --passes 1 --global-photons 5000 -q");
        EXPECT_EQ(r.status, 0) << method << ": " << r.output;
        EXPECT_TRUE(fs::exists(out)) << method;
        fs::remove(out);
        fs::remove(fs::path(out).replace_extension(".png"));
    }
    photoncl_cli::Result path4 = photoncl_cli::run("render " + path + " -o " + out + " --method path --passes 2 -q");
    EXPECT_EQ(path4.status, 0) << path4.output;
    EXPECT_TRUE(fs::exists(out));
    fs::remove(out);
    fs::remove(fs::path(out).replace_extension(".png"));
    fs::remove(path);
}
