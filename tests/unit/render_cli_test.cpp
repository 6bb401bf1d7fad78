// `photoncl render` with the photon-mapping methods: options, output with metadata and AOV
// layers, the device rules, and Ctrl-C writing the passes done.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

#include <unistd.h>

#include "common/optional_feature.h"
#include "core/error.h"
#include "image/image_io.h"
#include "unit/run_photoncl.h"

namespace fs = std::filesystem;
using photoncl_cli::Result;
using photoncl_cli::run;

namespace {

std::string scene(const std::string& name) { return (fs::path(PHOTONCL_SOURCE_DIR) / "scenes" / name).string(); }

class RenderCliTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl-render-cli-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    fs::path dir;
    // Tiny photon renders: seconds each under PoCL.
    const std::string small =
        " --width 16 --height 16 --strata 1 --global-photons 4000 --caustic-photons 4000 --gather-rays 4 -q";
};

}  // namespace

TEST_F(RenderCliTest, EveryPhotonMethodWritesAFiniteImageWithItsMetadata) {
    for (const char* method : {"fg", "direct", "progressive"}) {
        fs::path out = dir / (std::string(method) + ".exr");
        Result r = run("render " + scene("cornell-spheres.json") + " --method " + method + " --passes 2 --seed 9 -o " +
                       out.string() + small);
        ASSERT_EQ(r.status, 0) << method << ": " << r.output;
        pcl::ImageMetadata meta;
        pcl::Image img = pcl::readImage(out.string(), &meta);
        EXPECT_EQ(meta.method, method);
        EXPECT_EQ(meta.seed, 9u);
        EXPECT_EQ(meta.samples, 2);  // 2 passes × 1 sample
        double sum = 0;
        for (float v : img.rgb) {
            ASSERT_TRUE(std::isfinite(v)) << method;
            sum += v;
        }
        EXPECT_GT(sum, 0.0) << method;
        EXPECT_TRUE(fs::exists(dir / (std::string(method) + ".png")));
    }
}

TEST_F(RenderCliTest, AovLayersAndStageTimes) {
    fs::path out = dir / "aov.exr";
    Result r = run("render " + scene("cornell-box.json") + " --passes 1 --aov direct,indirect,albedo,normal -o " +
                   out.string() + " --width 16 --height 16 --global-photons 4000 --gather-rays 4");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* line : {"time by stage", "photon pass", "eye paths", "direct light", "indirect", "gather rays 4"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
    Result info = run("compare " + out.string() + " " + out.string());  // the EXR reads back
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_EQ(run("render " + scene("cornell-box.json") + " --aov sparkle -o " + out.string() + small).status, 2);
}

// --profile: the device seconds of every kernel per pass, and the photon pass per pass (the first
// apart: it loads the kernels) with its paths per second (4000 paths a pass here).
TEST_F(RenderCliTest, ProfileTimesEveryKernelAndThePhotonPassPerPass) {
    Result r = run("render " + scene("cornell-box.json") + " --method fg --passes 3 --profile -o " +
                   (dir / "p.exr").string() +
                   " --width 16 --height 16 --strata 1 --global-photons 4000 --gather-rays 4");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* line : {"device time by kernel", "emit_photons", "trace_photons_global", "final_gather_trace"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m,
                                  std::regex("photon pass: first pass ([0-9.]+) ms, later passes median ([0-9.]+) ms "
                                             "\\(([0-9.]+)-([0-9.]+)\\): ([0-9.]+) M paths a second")))
        << r.output;
    const double median = std::stod(m[2]), lo = std::stod(m[3]), hi = std::stod(m[4]), rate = std::stod(m[5]);
    EXPECT_GT(std::stod(m[1]), 0.0);
    EXPECT_LE(lo, median);
    EXPECT_LE(median, hi);
    ASSERT_GT(median, 0.0);
    EXPECT_NEAR(rate / (4000.0 / median * 1e-3), 1.0, 0.01) << "both printed to 3-4 digits";
}

// The parts sum to the image: per pixel, beauty = direct + caustic + indirect + emitted (every
// layer read back from the EXR; cornell-spheres has all four: lamp, caustics, indirect light), so
// a part left out, counted twice or written to the wrong layer fails. The beauty is summed in
// fixed point (2^-32 steps), the parts as doubles: they agree to float rounding (6.5e-8 measured;
// leaving the emitted layer out of the sum fails at the first lamp pixel, 20.2 against 0.2).
TEST_F(RenderCliTest, AovPartsSumToTheImagePerPixel) {
    using namespace pcl;
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO");
    const fs::path out = dir / "parts.exr";
    Result r = run("render " + scene("cornell-spheres.json") +
                   " --passes 2 --strata 2 --gather-rays 4 --light-samples 2 --width 24 --height 24"
                   " --global-photons 20000 --caustic-photons 20000 --aov direct,caustic,indirect,emitted,albedo"
                   " -q -o " +
                   out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const Image beauty = readImage(out.string());
    const char* parts[] = {"direct", "caustic", "indirect", "emitted"};
    std::vector<Image> layers;
    for (const char* p : parts) layers.push_back(readImageLayer(out.string(), p));
    double partTotal[4] = {0, 0, 0, 0}, worst = 0.0;
    for (size_t i = 0; i < beauty.rgb.size(); ++i) {
        double sum = 0.0;
        for (int k = 0; k < 4; ++k) {
            sum += layers[k].rgb[i];
            partTotal[k] += layers[k].rgb[i];
        }
        ASSERT_TRUE(std::isfinite(beauty.rgb[i])) << "value " << i;
        const double err = std::abs(beauty.rgb[i] - sum) / std::max(1.0, std::abs(sum));
        worst = std::max(worst, err);
        ASSERT_LE(err, 1e-6) << "value " << i << ": image " << beauty.rgb[i] << ", parts " << sum;
    }
    std::printf("[figure] AOV parts vs image: worst relative difference %.3g\n", worst);
    for (int k = 0; k < 4; ++k) EXPECT_GT(partTotal[k], 0.0) << parts[k] << " is empty";  // each part present
    EXPECT_THROW(readImageLayer(out.string(), "sparkle"), InputError);
}

// --device ref renders the photon methods on the CPU twin with no OpenCL at all (the ICD loader
// pointed at nothing finds no platform): the same image as the device's, up to what the render
// twin test allows with each side's own photon pass (image means within 5e-3; there measured
// ≤ 1.7e-3), the metadata naming the twin.
TEST_F(RenderCliTest, DeviceRefRendersEveryMethodOnTheTwinWithoutOpenCL) {
    for (const char* method : {"fg", "direct", "progressive"}) {
        const std::string args = "render " + scene("cornell-spheres.json") + " --method " + method +
                                 " --passes 2 --seed 5" + small + " -o ";
        Result ref = run(args + (dir / "ref.exr").string() + " --device ref", "OCL_ICD_VENDORS=/nonexistent");
        ASSERT_EQ(ref.status, 0) << method << ": " << ref.output;
        Result dev = run(args + (dir / "dev.exr").string());
        ASSERT_EQ(dev.status, 0) << method << ": " << dev.output;
        pcl::ImageMetadata refMeta, devMeta;
        const pcl::Image a = pcl::readImage((dir / "ref.exr").string(), &refMeta);
        const pcl::Image b = pcl::readImage((dir / "dev.exr").string(), &devMeta);
        EXPECT_EQ(refMeta.device, "ref");
        EXPECT_EQ(refMeta.samples, devMeta.samples);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        double sa = 0.0, sb = 0.0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            ASSERT_TRUE(std::isfinite(a.rgb[i])) << method << " value " << i;
            sa += a.rgb[i];
            sb += b.rgb[i];
        }
        ASSERT_GT(sb, 0.0) << method;
        std::printf("[figure] render --device ref %s: sum of the image %.6g, the device's %.6g (rel %.2e)\n", method,
                    sa, sb, std::abs(sa - sb) / sb);
        EXPECT_LE(std::abs(sa - sb) / sb, 5e-3) << method;
    }
    // What only an OpenCL device has is refused, naming the twin.
    Result profile = run("render " + scene("cornell-box.json") + " --method fg --device ref --profile -o " +
                         (dir / "x.exr").string() + small);
    EXPECT_EQ(profile.status, 2) << profile.output;
    EXPECT_NE(profile.output.find("--device ref"), std::string::npos) << profile.output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    Result path = run("render " + scene("cornell-box.json") + " --method path --device ref --passes 1 -o " +
                      (dir / "p.exr").string() + " --width 8 --height 8 -q");
    EXPECT_EQ(path.status, 0) << path.output;
}

TEST_F(RenderCliTest, HelpExplainsEveryOption) {
    Result r = run("render --help");
    ASSERT_EQ(r.status, 0);
    for (const char* opt : {"--method",
                            "--device",
                            "--passes",
                            "--time",
                            "--strata",
                            "--global-photons",
                            "--caustic-photons",
                            "--k",
                            "--caustic-k",
                            "--gather-rays",
                            "--light-samples",
                            "--gather-source",
                            "--gather-importance",
                            "--filter",
                            "--visibility",
                            "--radius",
                            "--alpha",
                            "--aov",
                            "--max-buffer-mib",
                            "progressive",
                            "auto (the default)",
                            "Ctrl-C"})
        EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
}

// --visibility reaches the renderer: its settings line (logged and in the EXR) says so.
TEST_F(RenderCliTest, VisibilityFlagReachesTheRenderer) {
    Result r = run("render " + scene("cornell-box.json") + " -o " + (dir / "v.exr").string() + small +
                   " --passes 1 --no-png --visibility");
    ASSERT_EQ(r.status, 0) << r.output;
    pcl::ImageMetadata meta;
    pcl::readImage((dir / "v.exr").string(), &meta);
    bool found = false;
    for (const auto& kv : meta.extra) found |= kv.second.find("visibility test") != std::string::npos;
    EXPECT_TRUE(found) << "the EXR's settings should record the visibility test";
}

TEST_F(RenderCliTest, DefaultsAreLoggedWithTheirReasons) {
    Result r = run("render " + scene("cornell-box.json") + " --passes 1 -o " + (dir / "d.exr").string() +
                   " --width 8 --height 8 --global-photons 2000 --gather-rays 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("(default: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(given)"), std::string::npos) << r.output;
}

// Ctrl-C (SIGINT after 4 s, from coreutils timeout) ends the render after its current pass
// and writes the image of the passes done, exit status 0.
TEST_F(RenderCliTest, InterruptWritesThePassesDone) {
    fs::path out = dir / "int.exr";
    std::string cmd = "timeout --preserve-status -s INT 4 " + std::string(PHOTONCL_BINARY) + " render " +
                      scene("cornell-box.json") + " --method progressive --passes 1000000 -o " + out.string() + small +
                      " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    int raw = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(raw)) << output;
    EXPECT_EQ(WEXITSTATUS(raw), 0) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    ASSERT_TRUE(fs::exists(out)) << output;
    pcl::ImageMetadata meta;
    pcl::Image img = pcl::readImage(out.string(), &meta);
    EXPECT_GT(meta.samples, 0);
    EXPECT_LT(meta.samples, 1000000);
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));
    size_t files = 0;
    for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 2u);  // the EXR and the PNG, no temporary left
}

// A 4 MiB buffer cap splits the eye samples into many more chunks (and the photon and kNN
// batches): the image keeps every bit (random numbers are keyed by pixel and sample).
TEST_F(RenderCliTest, BufferCapKeepsTheImageBits) {
    std::string common =
        " --width 32 --height 32 --passes 1 --global-photons 20000 --caustic-photons 10000 -q --no-png";
    ASSERT_EQ(run("render " + scene("cornell-spheres.json") + " -o " + (dir / "a.exr").string() + common).status, 0);
    ASSERT_EQ(run("render " + scene("cornell-spheres.json") + " -o " + (dir / "b.exr").string() + common +
                  " --max-buffer-mib 4")
                  .status,
              0);
    Result same = run("compare " + (dir / "b.exr").string() + " " + (dir / "a.exr").string() + " --max-rmse 0");
    EXPECT_EQ(same.status, 0) << same.output;
}

// --method auto: the pilot logs its figures and its choice (the method with the lower relMSE
// predicted at the budget: relMSE × seconds / T, plus fg's squared bias), the render then uses it
// (the metadata names it) within the time budget; with
// --device ref it is refused, since the pilot times fg on an OpenCL device.
TEST_F(RenderCliTest, AutoMethodRendersWithThePilotsChoice) {
    const fs::path out = dir / "auto.exr";
    Result r =
        run("render " + scene("cornell-box.json") + " --method auto --width 32 --time 4 --seed 3 -o " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    // "method auto: fg (pilot 1.2 s: relMSE x seconds at full size fg 0.0151 (2.840 s a pass) + bias
    // 0, path 0.0413 (0.048 s a sample per pixel); the lowest relMSE at 4.0 s wins: …)": the choice
    // is the candidate with the lowest product / T + bias.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        r.output, m, std::regex(R"(method auto: ([\w ]+?) \(pilot [0-9.]+ s: (.*); the lowest relMSE at ([0-9.]+) s)")))
        << r.output;
    const std::string chosen = m[1].str(), figures = m[2].str();
    const double T = std::stod(m[3].str());
    EXPECT_GT(T, 0.0) << r.output;
    std::string best;
    double bestPredicted = INFINITY;
    const std::regex candidate(R"((fg 6x6x2|fg|path) ([0-9.e+-]+) \([^)]*\)( \+ bias ([0-9.e+-]+))?)");
    for (auto it = std::sregex_iterator(figures.begin(), figures.end(), candidate); it != std::sregex_iterator();
         ++it) {
        const double product = std::stod((*it)[2]);
        const double bias = (*it)[4].matched ? std::stod((*it)[4]) : 0.0;
        EXPECT_TRUE(std::isfinite(product) && product > 0) << r.output;
        EXPECT_TRUE(std::isfinite(bias) && bias >= 0) << r.output;
        const double predicted = product / T + bias;
        if (predicted < bestPredicted) bestPredicted = predicted, best = (*it)[1].str();
    }
    EXPECT_EQ(chosen, best) << r.output;
    pcl::ImageMetadata meta;
    const pcl::Image img = pcl::readImage(out.string(), &meta);
    EXPECT_EQ(meta.method, chosen.substr(0, chosen.find(' ')));
    EXPECT_LT(meta.seconds, 4.0 + 3.0) << "the pilot is paid from --time; a last pass may overrun";
    for (float v : img.rgb) ASSERT_TRUE(std::isfinite(v));

    Result ref = run("render " + scene("cornell-box.json") + " --method auto --device ref --width 16 -q -o " +
                     (dir / "ref.exr").string());
    EXPECT_EQ(ref.status, pcl::kExitBadInput) << ref.output;
    EXPECT_NE(ref.output.find("--method auto pilots fg on an OpenCL device"), std::string::npos) << ref.output;
}

// No --method: auto, unless the command line names what only a photon method reads (--passes,
// --device ref, a photon option such as --aov), which gives fg, each with its reason logged.
TEST_F(RenderCliTest, DefaultMethodIsAutoUnlessTheCommandLineSaysOtherwise) {
    Result a =
        run("render " + scene("cornell-box.json") + " --width 32 --time 3 --no-png -o " + (dir / "a.exr").string());
    ASSERT_EQ(a.status, 0) << a.output;
    EXPECT_NE(a.output.find("method auto: "), std::string::npos) << a.output;
    pcl::ImageMetadata meta;
    pcl::readImage((dir / "a.exr").string(), &meta);
    EXPECT_TRUE(meta.method == "fg" || meta.method == "path") << meta.method;

    const struct {
        std::string args, reason;
    } fg[] = {{" --passes 1" + small, "method fg: --passes counts passes of a photon method"},
              {" --time 1 --width 16 --aov albedo", "method fg: --aov is an option of the photon methods"},
              {" --passes 1 --device ref --width 8 --global-photons 2000 --gather-rays 2",
               "method fg: --device ref runs the photon methods' CPU twins"}};
    for (const auto& c : fg) {
        Result r = run("render " + scene("cornell-box.json") + " --no-png -o " + (dir / "fg.exr").string() + c.args);
        ASSERT_EQ(r.status, 0) << c.args << "\n" << r.output;
        if (c.args.find(" -q") == std::string::npos) {
            EXPECT_NE(r.output.find(c.reason), std::string::npos) << c.args << "\n" << r.output;
        }
        EXPECT_EQ(r.output.find("method auto"), std::string::npos) << c.args << "\n" << r.output;
        pcl::readImage((dir / "fg.exr").string(), &meta);
        EXPECT_EQ(meta.method, "fg") << c.args;
    }
}
