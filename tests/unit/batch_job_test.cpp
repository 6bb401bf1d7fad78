// Batch job files: every key checked, paths relative to the job file, render
// defaults for what is left out, shard pass ranges that tile [0, P).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "batch/batch_job.h"
#include "core/error.h"
#include "render/photon_renderer.h"

namespace fs = std::filesystem;
using namespace pcl;

namespace {

class BatchJobTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl-batch-job-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir / "jobs");
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string write(const std::string& text) {
        std::string p = (dir / "jobs" / "job.json").string();
        std::ofstream(p) << text;
        return p;
    }
    std::string scene() const { return (fs::path(PHOTONCL_SOURCE_DIR) / "scenes" / "cornell-spheres.json").string(); }
    std::string error(const std::string& text) {
        try {
            loadBatchJob(write(text));
        } catch (const InputError& e) {
            return e.what();
        }
        return "(no error)";
    }
    fs::path dir;
};

}  // namespace

TEST_F(BatchJobTest, ReadsEveryFieldAndResolvesPathsAgainstTheJobFile) {
    BatchJob job =
        loadBatchJob(write(R"({"scene": ")" + scene() + R"(", "output": "../out/x.exr", "method": "progressive",
        "passes": 12, "shards": 5, "seed": 7, "width": 40, "height": 30, "globalPhotons": 1000, "causticPhotons": 500,
        "strata": 2, "k": 20, "causticK": 30, "lightSamples": 4, "alpha": 0.5, "filter": "box",
        "structure": "hash-grid", "visibility": true, "device": "cpu", "maxBufferMib": 64, "caustics": "map",
        "emitterStrata": 8})"));
    EXPECT_EQ(job.output, (dir / "out" / "x.exr").lexically_normal().string());
    EXPECT_EQ(job.method, "progressive");
    EXPECT_EQ(job.passes, 12u);
    EXPECT_EQ(job.shards, 5u);
    EXPECT_EQ(job.seed, 7u);
    EXPECT_EQ(job.width, 40);
    EXPECT_EQ(job.height, 30);
    EXPECT_EQ(job.globalPhotons, 1000u);
    EXPECT_EQ(job.strata, 2u);
    EXPECT_FLOAT_EQ(job.alpha, 0.5f);
    EXPECT_EQ(job.structure, "hash-grid");
    EXPECT_TRUE(job.visibility);
    EXPECT_EQ(job.maxBufferMib, 64u);
    EXPECT_EQ(job.caustics, "map");
    EXPECT_EQ(job.emitterStrata, 8);
    EXPECT_EQ(shardPath(job, 3),
              (dir / "out" / "x.exr.shards" / "shard-0003-of-0005.pcls").lexically_normal().string());
    EXPECT_EQ(manifestPath(job), (dir / "out" / "x.manifest.json").lexically_normal().string());
}

TEST_F(BatchJobTest, LeftOutSettingsTakeTheRenderDefaults) {
    // cornell-spheres is 256x256 (fg: 10 passes at 256², scaled by pixels); width alone keeps the aspect.
    BatchJob job = loadBatchJob(write(R"({"scene": ")" + scene() + R"(", "output": "x.exr", "shards": 2})"));
    EXPECT_EQ(job.method, "fg");
    EXPECT_EQ(job.width, 256);
    EXPECT_EQ(job.height, 256);
    EXPECT_EQ(job.passes, defaultPasses(RenderMethod::FinalGather, 256, 256));
    BatchJob half =
        loadBatchJob(write(R"({"scene": ")" + scene() + R"(", "output": "x.exr", "shards": 1, "width": 128})"));
    EXPECT_EQ(half.height, 128);
    EXPECT_EQ(half.passes, defaultPasses(RenderMethod::FinalGather, 128, 128));
    BatchJob path =
        loadBatchJob(write(R"({"scene": ")" + scene() + R"(", "output": "x.exr", "shards": 4, "method": "path"})"));
    EXPECT_EQ(path.passes, 64u);       // render --method path's 64 samples per pixel
    EXPECT_EQ(job.emitterStrata, -1);  // render's default
    EXPECT_EQ(job.caustics, "");
}

TEST_F(BatchJobTest, BadJobsNameTheKeyAndWhatWasExpected) {
    const std::string head = R"({"scene": ")" + scene() + R"(", "output": "x.exr", )";
    std::string e = error(head + R"("shards": 2, "passes": 4, "photons": 5})");
    EXPECT_NE(e.find("photons"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
    EXPECT_NE(e.find("globalPhotons"), std::string::npos) << e;  // the allowed keys are listed
    e = error(head + R"("shards": 2, "passes": 4, "method": "pt"})");
    EXPECT_NE(e.find("\"path\""), std::string::npos) << e;  // the methods are listed
    e = error(head + R"("shards": 0, "passes": 4})");
    EXPECT_NE(e.find("shards"), std::string::npos) << e;
    e = error(head + R"("shards": 5, "passes": 4})");
    EXPECT_NE(e.find("at most the number of passes"), std::string::npos) << e;
    e = error(head + R"("shards": 2, "passes": -3})");
    EXPECT_NE(e.find("passes: expected an integer"), std::string::npos) << e;
    e = error(head + R"("shards": 2, "passes": 4, "visibility": 1})");
    EXPECT_NE(e.find("visibility: expected true or false"), std::string::npos) << e;
    e = error(head + R"("shards": 2, "passes": 4, "emitterStrata": 17})");
    EXPECT_NE(e.find("emitterStrata: expected an integer in [0, 16]"), std::string::npos) << e;
    e = error(head + R"("shards": 2, "passes": 4, "filter": "tent"})");
    EXPECT_NE(e.find("filter"), std::string::npos) << e;
    e = error(R"({"output": "x.exr", "shards": 2})");
    EXPECT_NE(e.find("scene"), std::string::npos) << e;
    e = error(R"({"scene": "missing.json", "output": "x.exr", "shards": 2})");
    EXPECT_NE(e.find("missing.json"), std::string::npos) << e;
    e = error("[1, 2]");
    EXPECT_NE(e.find("an object"), std::string::npos) << e;
}

TEST_F(BatchJobTest, ShardRangesTileThePassesExactlyOnce) {
    BatchJob job;
    for (uint32_t passes : {1u, 7u, 10u, 1000u, 4294967u})
        for (uint32_t shards : {1u, 2u, 3u, 7u, 64u}) {
            if (shards > passes) continue;
            job.passes = passes;
            job.shards = shards;
            uint32_t next = 0, smallest = UINT32_MAX, largest = 0;
            for (uint32_t i = 0; i < shards; ++i) {
                PassRange r = shardPasses(job, i);
                ASSERT_EQ(r.first, next) << passes << "/" << shards;
                ASSERT_GT(r.count(), 0u);
                smallest = std::min(smallest, r.count());
                largest = std::max(largest, r.count());
                next = r.end;
            }
            EXPECT_EQ(next, passes);
            EXPECT_LE(largest - smallest, 1u);  // balanced
        }
}
