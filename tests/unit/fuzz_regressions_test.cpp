// The fuzz regressions (tests/fuzz/regressions/{json,gltf}/): inputs a fuzzer once crashed on and
// hand-made edge cases, loaded in the normal build exactly as the libFuzzer harnesses load them
// (tests/fuzz/*_loader_fuzz.cpp). Each must end as a Scene or an InputError that names the file;
// a crash or a sanitizer report kills this test's process, which CTest counts as a failure. The
// folders are required: a missing or empty one fails, so the regressions cannot silently stop
// running.
//
// The file name says what the outcome must be:
//   valid-*                            must load (and pass validateScene);
//   crash-*, leak-*, timeout-*, oom-*  (libFuzzer's artifact names) may load or give an InputError:
//                                      only the crash was the bug;
//   anything else                      a hand-made bad input: must give an InputError.
#include <gtest/gtest.h>
#include "common/optional_feature.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/json_loader.h"
#include "scene/validate.h"

namespace fs = std::filesystem;
using namespace pcl;

namespace {

// The folder does not exist, so includes and buffer files fail as missing, never read real files.
const std::string kJsonPath = "photoncl-fuzz-no-such-dir/scene.json";
const std::string kGltfPath = "photoncl-fuzz-no-such-dir/scene.gltf";

enum class Outcome { Loaded, InputError, OtherException };

struct LoadResult {
    Outcome outcome;
    std::string message;
};

LoadResult loadLikeHarness(const std::string& kind, const std::string& bytes) {
    try {
        Scene scene;
        if (kind == "json") {
            scene = parseJsonScene(bytes, kJsonPath);
        } else {
#ifdef PHOTONCL_HAVE_GLTF
            scene.path = kGltfPath;
            GltfImportResult r = importGltfFromMemory(scene, std::vector<unsigned char>(bytes.begin(), bytes.end()),
                                                      scene.path, GltfImportOptions{});
            if (r.hasCamera) scene.camera = r.camera;
#endif
        }
        validateScene(scene);
        return {Outcome::Loaded, ""};
    } catch (const InputError& e) {
        return {Outcome::InputError, e.what()};
    } catch (const std::exception& e) {
        return {Outcome::OtherException, e.what()};
    }
}

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

void checkRegressions(const std::string& kind) {
    const fs::path dir = fs::path(PHOTONCL_SOURCE_DIR) / "tests" / "fuzz" / "regressions" / kind;
    ASSERT_TRUE(fs::is_directory(dir)) << dir << " is missing: the fuzz regressions are required";
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    // At least the hand-made edge cases committed with this test (21 JSON, 31 glTF); fewer means
    // some were lost.
    ASSERT_GE(files.size(), 10u) << dir << " holds " << files.size() << " files: the fuzz regressions are required";

    const std::string& scenePath = kind == "json" ? kJsonPath : kGltfPath;
    size_t loaded = 0, refused = 0;
    for (const fs::path& path : files) {
        std::ifstream in(path, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string name = path.filename().string();
        SCOPED_TRACE(path.string());
        LoadResult r = loadLikeHarness(kind, bytes);
        ASSERT_NE(r.outcome, Outcome::OtherException) << "not an InputError: " << r.message;
        if (r.outcome == Outcome::InputError) {
            ++refused;
            // The message shape every loader error has: "FILE: FIELD: expected X, got Y".
            EXPECT_NE(r.message.find(scenePath), std::string::npos)
                << "the error does not name the file: " << r.message;
        } else {
            ++loaded;
        }
        if (startsWith(name, "valid-")) {
            EXPECT_EQ(r.outcome, Outcome::Loaded) << "a valid input was refused: " << r.message;
        } else if (!(startsWith(name, "crash-") || startsWith(name, "leak-") || startsWith(name, "timeout-") ||
                     startsWith(name, "oom-"))) {
            EXPECT_EQ(r.outcome, Outcome::InputError) << "a bad input loaded without an error";
        }
    }
    ::testing::Test::RecordProperty("files", int(files.size()));
    std::printf("%s regressions: %zu files, %zu loaded, %zu refused with an InputError\n", kind.c_str(), files.size(),
                loaded, refused);
}

}  // namespace

TEST(FuzzRegressions, JsonLoaderGivesSceneOrInputError) { checkRegressions("json"); }

TEST(FuzzRegressions, GltfLoaderGivesSceneOrInputError) {
#ifndef PHOTONCL_HAVE_GLTF
    PCL_REQUIRE_FEATURE(false, "glTF support (tinygltf)");
#endif
    checkRegressions("gltf");
}
