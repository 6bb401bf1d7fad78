// The environment light ("sky"): the equirectangular mapping (Mitsuba 3's), exact importance
// sampling of a texel map (χ² against the texels' shares of ∫ Y(L) dω, density ∝ the luminance Y), the JSON key
// "environment" and the messages that refuse bad skies, and the photon methods refusing a sky.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/math.h"
#include "image/image_io.h"
#include "prep/environment_map.h"
#include "reference/sampling.h"
#include "scene/json_loader.h"
#include "scene/load_scene.h"

using namespace pcl;
namespace fs = std::filesystem;

namespace {

// The test's own statement of the mapping: u = atan2(x, −z)/2π wrapped, v = acos(y)/π, after
// turning the world direction back by the rotation about +y.
void texelOf(Vec3 w, float degrees, int width, int height, int& x, int& y) {
    const double a = -double(degrees) * kPiD / 180.0;
    const double lx = std::cos(a) * w.x + std::sin(a) * w.z, lz = -std::sin(a) * w.x + std::cos(a) * w.z;
    double u = std::atan2(lx, -lz) / (2.0 * kPiD);
    if (u < 0) u += 1.0;
    x = std::min(int(u * width), width - 1);
    y = std::min(int(std::acos(std::max(-1.0, std::min(1.0, double(w.y)))) / kPiD * height), height - 1);
}

Environment mapOf(Image image, float degrees, Vec3 scale = Vec3(1.0f)) {
    Environment e;
    e.image = std::move(image);
    e.scale = scale;
    e.rotationDegrees = degrees;
    return e;
}

}  // namespace

TEST(EnvironmentMap, MapsDirectionsToMitsubasTexels) {
    Image img(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) img.set(x, y, Vec3(float(1 + x + 4 * y)));
    const Environment env = mapOf(img, 0.0f, Vec3(2.0f));
    const EnvironmentMap map(env);
    // −z is u = 0, +x a quarter turn on, +z half, −x three quarters; up is row 0.
    EXPECT_EQ(map.radiance(normalize(Vec3(0, 0.1f, -1))).x, 2.0f * 1);
    EXPECT_EQ(map.radiance(normalize(Vec3(1, 0.1f, 0))).x, 2.0f * 2);
    EXPECT_EQ(map.radiance(normalize(Vec3(0, 0.1f, 1))).x, 2.0f * 3);
    EXPECT_EQ(map.radiance(normalize(Vec3(-1, 0.1f, 0))).x, 2.0f * 4);
    EXPECT_EQ(map.radiance(normalize(Vec3(-1, -0.1f, 0))).x, 2.0f * 8);
    // Turned by 90° about +y (right-handed, as Mitsuba's to_world rotate): the map's +z (u = 1/2)
    // now lies at world +x, its −x (u = 3/4) at world +z.
    const Environment turned = mapOf(img, 90.0f);
    EXPECT_EQ(EnvironmentMap(turned).radiance(normalize(Vec3(1, 0.1f, 0))).x, 3.0f);
    EXPECT_EQ(EnvironmentMap(turned).radiance(normalize(Vec3(0, 0.1f, 1))).x, 4.0f);
    EXPECT_FLOAT_EQ(map.integral().x,
                    2.0f * float(kPiD) / 2.0f * (1 + 2 + 3 + 4 + 5 + 6 + 7 + 8));  // each texel: π/2 sr
}

// 400 000 samples of a 16×8 map with zero texels, turned 30°: the counts per texel against the
// texels' shares (χ², 127 − zeros degrees of freedom), none in a dark texel, and every sample's
// density equal to pdf() and proportional to the radiance (exact importance sampling).
TEST(EnvironmentMap, SamplesTexelsByTheirShareOfTheIntegral) {
    const int W = 16, H = 8;
    Image img(W, H);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            img.set(x, y, (x + y) % 5 == 0 ? Vec3(0.0f) : Vec3(uni(rng), uni(rng), 4.0f * uni(rng)));
    const float degrees = 30.0f;
    const Environment env = mapOf(img, degrees, Vec3(1.0f, 2.0f, 0.5f));
    const EnvironmentMap map(env);

    std::vector<double> share(size_t(W * H));
    double total = 0.0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const Vec3 L = img.at(x, y) * Vec3(1.0f, 2.0f, 0.5f);
            const double omega = 2.0 * kPiD / W * (std::cos(kPiD * y / H) - std::cos(kPiD * (y + 1) / H));
            share[size_t(y * W + x)] = (0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z) * omega;  // luminance
            total += share[size_t(y * W + x)];
        }
    const int N = 400000;
    std::vector<int> count(size_t(W * H), 0);
    double worstPdf = 0.0, worstProportion = 0.0;
    for (int i = 0; i < N; ++i) {
        Vec3 w;
        float pdf;
        ASSERT_TRUE(map.sample(uni(rng), uni(rng), w, pdf));
        ASSERT_NEAR(length(w), 1.0f, 1e-5f);
        int x, y;
        texelOf(w, degrees, W, H, x, y);
        ++count[size_t(y * W + x)];
        worstPdf = std::max(worstPdf, std::abs(map.pdf(w) / pdf - 1.0));
        const Vec3 L = map.radiance(w);
        worstProportion =
            std::max(worstProportion, std::abs(pdf / ((0.2126 * L.x + 0.7152 * L.y + 0.0722 * L.z) / total) - 1.0));
    }
    double chi2 = 0.0;
    int dof = -1, inDark = 0;
    for (size_t t = 0; t < count.size(); ++t) {
        if (share[t] == 0.0) {
            inDark += count[t];
            continue;
        }
        const double expected = N * share[t] / total;
        chi2 += (count[t] - expected) * (count[t] - expected) / expected;
        ++dof;
    }
    std::printf("environment sampling: chi2 %.1f with %d dof, %d samples in dark texels, worst pdf mismatch %.2e, "
                "worst departure from pdf ∝ L %.2e\n",
                chi2, dof, inDark, worstPdf, worstProportion);
    EXPECT_EQ(inDark, 0);
    // χ² with ~100 dof: mean 100, σ 14; 170 is 5σ.
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof));
    // Float precision (measured 0 and 1.4e-7): a sample lands inside the texel it was drawn in.
    EXPECT_LT(worstPdf, 1e-5);
    EXPECT_LT(worstProportion, 1e-5);
}

// ∫ pdf dω = 1 and E[L/pdf] = ∫ L dω, by uniform directions (Monte Carlo, 1 %).
TEST(EnvironmentMap, DensityIntegratesToOne) {
    Image img(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) img.set(x, y, Vec3(float(1 + (x * 3 + y) % 7)));
    const Environment env = mapOf(img, -45.0f);
    const EnvironmentMap map(env);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    double pdfSum = 0.0, lSum = 0.0;
    const int N = 200000;
    for (int i = 0; i < N; ++i) {
        const Vec3 w = sampleUniformSphere(uni(rng), uni(rng));
        pdfSum += map.pdf(w) * 4.0 * kPiD;
        lSum += map.radiance(w).x * 4.0 * kPiD;
    }
    EXPECT_NEAR(pdfSum / N, 1.0, 0.01);
    EXPECT_NEAR(lSum / N / map.integral().x, 1.0, 0.01);
}

TEST(EnvironmentMap, ConstantSkyIsUniform) {
    Environment env;
    env.scale = Vec3(0.5f, 1.0f, 2.0f);
    const EnvironmentMap map(env);
    ASSERT_TRUE(map.active());
    for (Vec3 w : {Vec3(0, 1, 0), Vec3(0, -1, 0), normalize(Vec3(1, 2, 3))}) {
        EXPECT_EQ(map.radiance(w), env.scale);
        EXPECT_NEAR(map.pdf(w), 1.0 / (4.0 * kPiD), 1e-6);
    }
    EXPECT_NEAR(map.integral().z, 8.0 * kPiD, 1e-4);
    EXPECT_FALSE(EnvironmentMap(Environment{}).active());
}

// How widely the sky's light is spread: 4π sr for a constant sky; one bright texel among dim
// ones reads close to that texel's solid angle (its share of Y dω squared over its Ω, summed).
TEST(EnvironmentMap, EffectiveSolidAngleIsTheSpreadOfTheLight) {
    Environment constant;
    constant.scale = Vec3(0.6f, 0.8f, 1.0f);
    EXPECT_NEAR(EnvironmentMap(constant).effectiveSolidAngle(), 4.0 * kPiD, 1e-6);
    const int W = 64, H = 32;
    Image img(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) img.set(x, y, Vec3(1.0f));
    EXPECT_NEAR(EnvironmentMap(mapOf(img, 0.0f)).effectiveSolidAngle(), 4.0 * kPiD, 1e-3);
    img.set(10, 8, Vec3(1e6f));  // a sun: Ω of its row's texels, 2π/W (cos θ0 − cos θ1)
    const double omega = 2.0 * kPiD / W * (std::cos(kPiD * 8 / H) - std::cos(kPiD * 9 / H));
    const double spread = EnvironmentMap(mapOf(img, 0.0f)).effectiveSolidAngle();
    std::printf("[figure] effective solid angle: constant 4π, sun texel %.3e sr against its Ω %.3e sr\n", spread,
                omega);
    EXPECT_NEAR(spread / omega, 1.0, 0.01);
    EXPECT_FALSE(skyCausticsByEyeRays(Scene{}));  // no sky at all
}

// ---- The JSON key -------------------------------------------------------------------------

namespace {

struct SceneFolder {
    fs::path dir;
    SceneFolder() {
        dir = fs::temp_directory_path() /
              ("photoncl-env-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~SceneFolder() { fs::remove_all(dir); }
    std::string write(const std::string& environment) const {
        const std::string path = (dir / "scene.json").string();
        std::ofstream(path)
            << R"({"camera": {"position": [0, 1, 5], "look_at": [0, 0, 0], "fov": 40, "resolution": [8, 8]},
            "materials": [{"name": "white", "rho_d": [0.5, 0.5, 0.5]}],
            "shapes": [{"type": "sphere", "material": "white", "centre": [0, 0, 0], "radius": 1}],
            "environment": )"
            << environment << "}";
        return path;
    }
};

void expectRefused(const SceneFolder& folder, const std::string& environment,
                   std::initializer_list<std::string> fragments) {
    try {
        loadJsonScene(folder.write(environment));
        ADD_FAILURE() << "loaded: " << environment;
    } catch (const InputError& e) {
        const std::string msg = e.what();
        for (const std::string& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' in: " << msg;
    }
}

}  // namespace

TEST(EnvironmentScene, LoadsAConstantAndAnImageSky) {
    SceneFolder folder;
    // The sky is the scene's only light: valid.
    Scene s = loadScene(folder.write(R"({"radiance": [0.1, 0.2, 0.3]})"));
    EXPECT_TRUE(s.environment.active());
    EXPECT_EQ(s.environment.scale, Vec3(0.1f, 0.2f, 0.3f));
    EXPECT_TRUE(s.environment.image.rgb.empty());

    Image sky(4, 2);
    sky.set(1, 0, Vec3(3.0f, 2.0f, 1.0f));
    writePfm((folder.dir / "sky.pfm").string(), sky);
    s = loadJsonScene(folder.write(R"({"image": "sky.pfm", "scale": 2, "rotation": 90})"));
    ASSERT_EQ(s.environment.image.width, 4);
    EXPECT_EQ(s.environment.image.at(1, 0), Vec3(3.0f, 2.0f, 1.0f));
    EXPECT_EQ(s.environment.scale, Vec3(2.0f));
    EXPECT_FLOAT_EQ(s.environment.rotationDegrees, 90.0f);

    // The HDR formats a user's sky comes in: OpenEXR and Radiance RGBE (.hdr), read the same.
    if (!haveOpenImageIO()) return;  // (a build without OpenImageIO reads PFM only)
    writeLinearImage((folder.dir / "sky.exr").string(), sky, ImageMetadata{});
    s = loadJsonScene(folder.write(R"({"image": "sky.exr"})"));
    ASSERT_EQ(s.environment.image.width, 4);
    EXPECT_EQ(s.environment.image.at(1, 0), Vec3(3.0f, 2.0f, 1.0f));
    // 4 × 2 flat RGBE pixels (no run-length coding below 8 wide): (3, 2, 1) = (192, 128, 64) × 2^(130-136).
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
    for (int i = 0; i < 8; ++i) hdr += i == 1 ? std::string("\xC0\x80\x40\x82", 4) : std::string(4, '\0');
    std::ofstream(folder.dir / "sky.hdr", std::ios::binary) << hdr;
    s = loadJsonScene(folder.write(R"({"image": "sky.hdr"})"));
    ASSERT_EQ(s.environment.image.width, 4);
    ASSERT_EQ(s.environment.image.height, 2);
    EXPECT_NEAR(s.environment.image.at(1, 0).x, 3.0f, 0.02f);
    EXPECT_NEAR(s.environment.image.at(1, 0).y, 2.0f, 0.02f);
    EXPECT_NEAR(s.environment.image.at(1, 0).z, 1.0f, 0.02f);
    EXPECT_EQ(s.environment.image.at(0, 0), Vec3(0.0f));
}

TEST(EnvironmentScene, RefusesBadSkiesWithTheUsualMessage) {
    SceneFolder folder;
    expectRefused(folder, R"({"radiance": [1, 1, 1], "image": "sky.pfm"})",
                  {"scene.json: environment: expected either \"radiance\"", "got both"});
    expectRefused(folder, R"({})", {"environment: expected either", "got neither"});
    expectRefused(folder, R"({"radiance": [0, 0, 0]})", {"environment.radiance", "not all zero"});
    expectRefused(folder, R"({"radiance": [1, -1, 1]})", {"environment.radiance", ">= 0"});
    expectRefused(folder, R"({"image": "missing.exr"})",
                  {"environment.image: expected a readable image", "missing.exr"});
    expectRefused(folder, R"({"image": "sky.png"})", {"environment.image: expected a linear HDR image", "sky.png"});
    expectRefused(folder, R"({"image": "../sky.exr"})", {"environment.image", "inside the scene's folder"});
    expectRefused(folder, R"({"radiance": [1, 1, 1], "rotation": "a lot"})", {"environment.rotation", "degrees"});
    expectRefused(folder, R"({"radiance": [1, 1, 1], "colour": 1})", {"environment.colour", "unknown key"});

    Image dark(2, 2);
    writePfm((folder.dir / "dark.pfm").string(), dark);
    expectRefused(folder, R"({"image": "dark.pfm"})", {"environment.image: expected an image with some light", "zero"});
    Image negative(2, 2);
    negative.set(1, 1, Vec3(1.0f, -0.5f, 1.0f));
    writePfm((folder.dir / "negative.pfm").string(), negative);
    expectRefused(folder, R"({"image": "negative.pfm"})",
                  {"environment.image: expected finite texels >= 0", "-0.5", "texel (1, 1)"});
    std::ofstream((folder.dir / "broken.exr").string()) << "not an image";
    expectRefused(folder, R"({"image": "broken.exr"})", {"environment.image: expected a readable image", "broken.exr"});
    Image sky(2, 1);
    sky.set(0, 0, Vec3(1.0f));
    writePfm((folder.dir / "sky.pfm").string(), sky);
    expectRefused(folder, R"({"image": "sky.pfm", "scale": 0})", {"environment.scale", "> 0"});
}

TEST(EnvironmentScene, PhotonMethodsRefuseASkyOnlyWithMedia) {
    SceneFolder folder;
    const Scene s = loadJsonScene(folder.write(R"({"radiance": [1, 1, 1]})"));
    EXPECT_NO_THROW(refuseEnvironmentInMediaWithoutPathTracer(s, "--method fg"));  // the photon methods read skies
    Scene fog = s;
    fog.media.push_back(Medium{"fog", Vec3(0.1f), Vec3(0.1f), 0.0f});
    fog.globalMedium = 0;
    try {
        refuseEnvironmentInMediaWithoutPathTracer(fog, "--method fg");
        ADD_FAILURE() << "not refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("environment: expected a scene without an environment light or without "
                                             "participating media for --method fg"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("a constant sky and 1 medium(s)"), std::string::npos) << e.what();
    }
    Scene plain = fog;
    plain.environment = Environment{};
    EXPECT_NO_THROW(refuseEnvironmentInMediaWithoutPathTracer(plain, "--method fg"));
}
