// Determinism through the command line: the same scene, seed and device give
// the same image bit for bit, run after run, whether the kernels come from a warm cache, a cold
// one (a fresh XDG_CACHE_HOME, PoCL's own cache off) or a damaged one (every cache file cut in
// half: rebuilt, not trusted; ProgramCache's own test, tests/stages/program_cache_test.cpp
// DamagedEntryIsRebuiltNotTrusted, covers the entry format: this one covers the whole program).
// The files' metadata hold seconds per stage, so the pixels are compared, not the files' bytes.
#include "stability/stability_common.h"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "image/image_io.h"
#include "unit/run_photoncl.h"

using namespace pcl;
namespace fs = std::filesystem;

namespace {

// Every pixel channel of `a` and `b` with the same bits.
size_t differingValues(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return size_t(-1);
    size_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) n += std::memcmp(&a.rgb[i], &b.rgb[i], sizeof(float)) != 0;
    return n;
}

}  // namespace

TEST(Determinism, FiveRunsSameSeedAreBitIdenticalWithWarmColdAndDamagedCaches) {
    ASSERT_TRUE(haveOpenImageIO());
    test::TempDir dir;
    const fs::path cache = dir.path() / "cache";
    const std::string scene = accuracy::scenePath("cornell-spheres.json");
    // Direct visualisation: fewer programs for the cold runs to compile than final gathering.
    const std::string args = " --method direct --width 24 --height 24 --passes 2 --strata 1 --global-photons 8000 "
                             "--caustic-photons 8000 --seed 41 -q --no-png -o ";
    auto withEnv = [&](const std::string& env, int run) {
        const fs::path out = dir.path() / ("run" + std::to_string(run) + ".exr");
        photoncl_cli::Result r = photoncl_cli::run("render " + scene + args + out.string(), env);
        EXPECT_EQ(r.status, 0) << r.output;
        return readImage(out.string());
    };
    const std::string warm = "XDG_CACHE_HOME=" + cache.string();
    const fs::path ours = cache / "photoncl";  // PoCL keeps its own cache beside it
    auto entries = [&] {
        std::vector<std::pair<fs::path, uintmax_t>> files;
        if (fs::is_directory(ours))
            for (auto& e : fs::recursive_directory_iterator(ours))
                if (e.is_regular_file()) files.emplace_back(e.path(), e.file_size());
        std::sort(files.begin(), files.end());
        return files;
    };
    // 1: cold (a fresh cache dir, PoCL's cache off); 2, 3: warm; 4: every photoncl cache file
    // cut in half first; 5: warm again (from the rebuilt files).
    std::vector<Image> runs;
    runs.push_back(withEnv(warm + " POCL_KERNEL_CACHE=0", 1));
    const auto cached = entries();
    runs.push_back(withEnv(warm, 2));
    runs.push_back(withEnv(warm, 3));
    for (const auto& [path, size] : cached) fs::resize_file(path, size / 2);
    runs.push_back(withEnv(warm, 4));
    const auto rebuilt = entries();
    runs.push_back(withEnv(warm, 5));
    size_t worst = 0;
    for (size_t i = 1; i < runs.size(); ++i) worst = std::max(worst, differingValues(runs[i], runs[0]));
    std::printf("[figure] determinism: 5 CLI runs (cold with POCL_KERNEL_CACHE=0, warm, warm, all %zu kernel-cache "
                "files cut in half, warm): %zu of %zu pixel values differ from run 1 (expected 0); mean %.5f\n",
                cached.size(), worst, runs[0].rgb.size(), accuracy::meanValue(runs[0]));
    EXPECT_GT(cached.size(), 0u) << "the cold run wrote no kernel cache under XDG_CACHE_HOME/photoncl";
    EXPECT_EQ(worst, 0u);
    EXPECT_GT(accuracy::meanValue(runs[0]), 0.0);
    // Rewritten whole: the same entries, none left at its cut size (a build with PoCL's cache on
    // may differ from the cold one by a few bytes, so sizes are not compared exactly).
    ASSERT_EQ(rebuilt.size(), cached.size());
    for (size_t i = 0; i < cached.size(); ++i) {
        EXPECT_EQ(rebuilt[i].first, cached[i].first);
        EXPECT_GT(rebuilt[i].second, cached[i].second / 2 + cached[i].second / 4) << rebuilt[i].first;
    }
}
