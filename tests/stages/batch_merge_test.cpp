// Batch merges on the device: the shards of a job, rendered separately and
// written to shard files, merge into exactly the bits of one renderPhotonMapped run of the same
// passes (N = 1, 2, 3, 7; fg and progressive, whose r_0 every shard computes from pass 0; the
// path tracer's shards merge exactly among themselves); a
// shard resumed after an interruption gives the same bits; mismatched, duplicated, overlapping,
// missing, incomplete and corrupt shards are refused; shards labelled with different devices
// merge, and merges of independently seeded shards pass the per-pixel Z-test against the
// one-run image (one OpenCL device here: seeds stand in for a second device's different
// floating point, see the test).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "batch/batch_job.h"
#include "batch/batch_render.h"
#include "batch/merge.h"
#include "batch/shard_file.h"
#include "core/error.h"
#include "device_fixture.h"
#include "image/metrics.h"
#include "reference/path_tracer.h"

namespace fs = std::filesystem;

namespace pcl {
namespace {

// 32×24, few photons: a pass takes tens of milliseconds under PoCL.
BatchScene smallJob(const fs::path& dir, const std::string& method, uint32_t passes, uint64_t seed) {
    std::string path = (dir / ("job-" + method + "-" + std::to_string(seed) + ".json")).string();
    std::ofstream(path)
        << R"({"scene": ")" << PHOTONCL_SOURCE_DIR << R"(/scenes/cornell-spheres.json", "output": "out-)" << method
        << seed << R"(.exr", "method": ")" << method << R"(", "passes": )" << passes << R"(, "shards": 1, "seed": )"
        << seed << R"(, "width": 32, "height": 24, "globalPhotons": 3000, "causticPhotons": 2000, "gatherRays": 8})";
    return loadBatchScene(loadBatchJob(path));
}

MergeExpectation expectationOf(const BatchScene& bs) {
    MergeExpectation e;
    e.sceneHash = bs.sceneHash;
    e.settingsHash = bs.settingsHash;
    e.settings = bs.settingsText;
    e.passes = bs.job.passes;
    e.width = bs.job.width;
    e.height = bs.job.height;
    return e;
}

// Renders every shard of bs split N ways to files; returns their paths.
std::vector<std::string> renderShards(BatchScene& bs, uint32_t shards) {
    bs.job.shards = shards;
    fs::create_directories(shardFolder(bs.job));
    std::vector<std::string> files;
    for (uint32_t i = 0; i < shards; ++i) {
        ShardData s = renderShard(&test::testDevice(), bs, i, shardPasses(bs.job, i), nullptr, {});
        files.push_back(shardPath(bs.job, i));
        writeShardFile(files.back(), s);
    }
    return files;
}

PhotonRenderResult renderOnce(const BatchScene& bs) {
    return renderPhotonMapped(test::testDevice(), bs.scene, bs.geometry, bs.buffers, bs.plan, bs.settings);
}

bool sameBits(const Image& a, const Image& b) {
    return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

std::string refusal(const std::vector<std::string>& files, const MergeExpectation& e, MergeOptions o = {}) {
    try {
        mergeShardFiles(files, e, o);
    } catch (const InputError& err) {
        return err.what();
    }
    return "(accepted)";
}

class BatchMergeTest : public ::testing::Test {
protected:
    test::TempDir dir;  // jobs, their shard folders and outputs
};

TEST_F(BatchMergeTest, ShardsOfAnyCountMergeToTheBitsOfOneRun) {
    for (const char* method : {"fg", "progressive"}) {
        BatchScene bs = smallJob(dir.path(), method, 7, 3);
        PhotonRenderResult once = renderOnce(bs);
        ASSERT_EQ(once.passes, 7u);
        const Image reference = once.film.resolve();
        for (uint32_t shards : {1u, 2u, 3u, 7u}) {
            std::vector<std::string> files = renderShards(bs, shards);
            MergedShards m = mergeShardFiles(files, expectationOf(bs), {});
            EXPECT_EQ(m.passesDone, 7u);
            EXPECT_FALSE(m.partial);
            const bool sums = m.film.sums() == once.sums.sums() && m.film.weights() == once.sums.weights();
            const bool image = sameBits(m.film.resolve(), reference);
            std::printf("[figure] %s, 7 passes in %u shard(s) merged vs one run: sums %s, image %s\n", method, shards,
                        sums ? "identical" : "DIFFER", image ? "bit-identical" : "DIFFERS");
            EXPECT_TRUE(sums) << method << " N=" << shards;
            EXPECT_TRUE(image) << method << " N=" << shards;
        }
    }
}

// The path tracer in a batch: pass p is sample p of every pixel, rounded to fixed point on its
// own, so any split merges to the bits of one shard of all the passes; `render --method path`
// sums its samples in doubles, so it agrees to rounding (1e-6 relative), not bit for bit.
TEST_F(BatchMergeTest, PathTracedShardsMergeExactlyAndAgreeWithThePathTracer) {
    BatchScene bs = smallJob(dir.path(), "path", 7, 3);
    std::vector<std::string> one = renderShards(bs, 1);
    const MergedShards whole = mergeShardFiles(one, expectationOf(bs), {});
    EXPECT_EQ(whole.shards.front().device, kPathTracerDevice);
    for (uint32_t shards : {2u, 3u, 7u}) {
        MergedShards m = mergeShardFiles(renderShards(bs, shards), expectationOf(bs), {});
        const bool same = m.film.sums() == whole.film.sums() && sameBits(m.film.resolve(), whole.film.resolve());
        std::printf("[figure] path, 7 samples in %u shard(s) merged vs 1 shard: %s\n", shards,
                    same ? "bit-identical" : "DIFFER");
        EXPECT_TRUE(same) << shards;
    }
    PathTracerSettings pt;
    pt.seed = 3;
    pt.samplesPerPixel = 7;
    const Image direct = PathTracer(bs.scene, bs.geometry, pt).render().resolve();
    const Image merged = whole.film.resolve();
    double worst = 0;
    for (size_t i = 0; i < direct.rgb.size(); ++i)
        worst = std::max(worst, std::fabs(double(direct.rgb[i]) - merged.rgb[i]) /
                                    std::max(1.0, double(std::fabs(direct.rgb[i]))));
    std::printf("[figure] path: merged shards vs render's path tracer (doubles), worst relative difference %.3g\n",
                worst);
    EXPECT_LE(worst, 1e-6);
}

TEST_F(BatchMergeTest, AShardResumedAfterAnInterruptionHasTheSameBits) {
    BatchScene bs = smallJob(dir.path(), "progressive", 6, 5);
    bs.job.shards = 2;
    const PassRange range = shardPasses(bs.job, 1);  // [3, 6)
    ShardData whole = renderShard(&test::testDevice(), bs, 1, range, nullptr, {});
    std::atomic<bool> stop{false};
    ShardRunOptions ro;
    ro.stop = &stop;
    ro.onPass = [&](uint32_t, uint32_t) { stop = true; };  // Ctrl-C during the first pass
    ShardData partial = renderShard(&test::testDevice(), bs, 1, range, nullptr, ro);
    EXPECT_EQ(partial.passesDone, 1u);
    EXPECT_FALSE(partial.complete());
    ShardData resumed = renderShard(&test::testDevice(), bs, 1, range, &partial, {});
    EXPECT_TRUE(resumed.complete());
    EXPECT_EQ(resumed.film.sums(), whole.film.sums());
    EXPECT_EQ(resumed.film.weights(), whole.film.weights());
    EXPECT_EQ(resumed.globalEmitted, whole.globalEmitted);
    EXPECT_EQ(resumed.accounting["runs"].size(), 2u);
}

TEST_F(BatchMergeTest, MismatchedDuplicatedMissingIncompleteAndCorruptShardsAreRefused) {
    BatchScene bs = smallJob(dir.path(), "fg", 4, 3);
    std::vector<std::string> three = renderShards(bs, 3);  // [0,1) [1,2) [2,4)
    const MergeExpectation expect = expectationOf(bs);
    // Duplicate: the same shard twice (a copy under another name).
    std::string copy = (fs::path(three[1]).parent_path() / "copy.pcls").string();
    fs::copy_file(three[1], copy);
    std::string why = refusal({three[0], three[1], copy, three[2]}, expect);
    EXPECT_NE(why.find("duplicates"), std::string::npos) << why;
    // Missing.
    why = refusal({three[0], three[2]}, expect);
    EXPECT_NE(why.find("passes [1, 2) are missing"), std::string::npos) << why;
    // Overlap: shard 0 of 2 holds [0, 2), overlapping shard 1 of 3.
    BatchScene two = smallJob(dir.path(), "fg", 4, 3);
    two.job.output = (dir.path() / "two.exr").string();
    std::vector<std::string> halves = renderShards(two, 2);
    why = refusal({halves[0], three[1], three[2]}, expect);
    EXPECT_NE(why.find("overlap"), std::string::npos) << why;
    // Other settings (seed) and another scene: named with what differs.
    BatchScene other = smallJob(dir.path(), "fg", 4, 4);
    std::vector<std::string> otherFiles = renderShards(other, 3);
    why = refusal({three[0], otherFiles[1], three[2]}, expect);
    EXPECT_NE(why.find(otherFiles[1] + ": rendered with other settings (seed 3 vs 4"), std::string::npos) << why;
    ShardData moved = readShardFile(three[2]);
    moved.sceneHash ^= 1;
    std::string movedPath = (dir.path() / "moved.pcls").string();
    writeShardFile(movedPath, moved);
    why = refusal({three[0], three[1], movedPath}, expect);
    EXPECT_NE(why.find("moved.pcls: rendered from another scene"), std::string::npos) << why;
    // Incomplete: refused unless allowPartial.
    ShardData partial = readShardFile(three[2]);
    partial.passesDone = 1;
    std::string partialPath = (dir.path() / "partial.pcls").string();
    writeShardFile(partialPath, partial);
    why = refusal({three[0], three[1], partialPath}, expect);
    EXPECT_NE(why.find("partial.pcls: incomplete: 1 of 2 passes"), std::string::npos) << why;
    MergeOptions allow;
    allow.allowPartial = true;
    EXPECT_TRUE(mergeShardFiles({three[0], three[1], partialPath}, expect, allow).partial);
    // Corrupt: one flipped bit in the payload.
    std::string bytes;
    {
        std::ifstream in(three[1], std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    bytes[bytes.size() - 100] ^= 4;
    std::string corrupt = (dir.path() / "corrupt.pcls").string();
    std::ofstream(corrupt, std::ios::binary) << bytes;
    why = refusal({three[0], corrupt, three[2]}, expect);
    EXPECT_NE(why.find("corrupt.pcls: checksum mismatch"), std::string::npos) << why;
    std::printf("[figure] refused merges name the file and the reason, e.g.:\n%s\n", why.c_str());
    // And the good set merges.
    EXPECT_EQ(mergeShardFiles(three, expect, {}).passesDone, 4u);
}

// Shards from different devices. Only one OpenCL device exists here (PoCL), so the two halves of
// the claim are tested separately and honestly:
//  1. the merge accepts shards whose files name different devices, lists both and marks the
//     image not bit-identical to a one-device run (the device label is rewritten in a real
//     shard file: the merge logic is what is tested);
//  2. a merge whose shards carry noise independent of the one-run image's (as a second device's
//     floating point would: its photon paths diverge after a few bounces) is statistically the
//     same image: K = 6 merges of 3 shards each, with seeds 10..15, against the seed-0 one-run
//     image, per-pixel Z-test with the reference's variance taken as the runs' (same settings,
//     same passes). A 30 % brighter merge must fail it (the test can fail).
TEST_F(BatchMergeTest, ShardsFromDifferentDevicesMergeAndPassTheZTest) {
    BatchScene bs = smallJob(dir.path(), "fg", 3, 0);
    std::vector<std::string> files = renderShards(bs, 3);
    ShardData relabelled = readShardFile(files[1]);
    relabelled.device = "another device (relabelled)";
    writeShardFile(files[1], relabelled);
    MergedShards mixed = mergeShardFiles(files, expectationOf(bs), {});
    ASSERT_EQ(mixed.devices.size(), 2u);
    nlohmann::json manifest = mergeManifest(mixed, bs.job.path, bs.job.scene, "x.exr", 0.0);
    EXPECT_FALSE(manifest["bitIdenticalToOneRun"].get<bool>());
    EXPECT_EQ(manifest["shards"].size(), 3u);

    const Image reference = renderOnce(bs).film.resolve();
    std::vector<Image> runs;
    for (uint64_t seed = 10; seed < 16; ++seed) {
        BatchScene other = smallJob(dir.path(), "fg", 3, seed);
        runs.push_back(mergeShardFiles(renderShards(other, 3), expectationOf(other), {}).film.resolve());
    }
    // The reference's variance: the runs' sample variance of the channel sum, per pixel.
    Image variance(reference.width, reference.height);
    const size_t pixels = size_t(reference.width) * reference.height;
    for (size_t p = 0; p < pixels; ++p) {
        double m = 0, m2 = 0;
        for (const Image& r : runs) m += r.rgb[3 * p] + r.rgb[3 * p + 1] + r.rgb[3 * p + 2];
        m /= runs.size();
        for (const Image& r : runs) {
            double d = r.rgb[3 * p] + r.rgb[3 * p + 1] + r.rgb[3 * p + 2] - m;
            m2 += d * d;
        }
        variance.rgb[3 * p] = float(m2 / (runs.size() - 1));
    }
    ZTestResult z = perPixelZTest(runs, reference, 4.0, &variance);
    std::printf("[figure] merges of shards seeded apart vs the one-run image: %s\n", formatZTest(z).c_str());
    EXPECT_EQ(z.nonFinite, 0u);
    EXPECT_GE(z.passFraction(), 0.97);  // t with 5 degrees of freedom: P(|t| < 4) = 0.990
    EXPECT_LT(z.meanAbsZ, 1.2);
    std::vector<Image> brighter = runs;
    for (Image& r : brighter)
        for (float& v : r.rgb) v *= 1.3f;
    ZTestResult biased = perPixelZTest(brighter, reference, 4.0, &variance);
    std::printf("[figure] the same merges 30 %% brighter: %s\n", formatZTest(biased).c_str());
    EXPECT_LT(biased.passFraction(), z.passFraction() - 0.05);
}

}  // namespace
}  // namespace pcl
