// `photoncl batch run` killed and resumed, with the real binary: SIGKILL in the
// middle of a render, in the middle of writing a shard file and between its fsync and rename
// (PHOTONCL_BATCH_TEST_PAUSE holds the process at those points) never leaves a file merge
// accepts under a shard's name, and never damages a shard written before; Ctrl-C (SIGINT)
// finishes the pass, writes an incomplete shard and exits 130; merge refuses it; `--all` skips
// complete shards, completes the incomplete one and renders the missing ones; a damaged shard is
// refused by merge and rendered again by `--all`; the final merge equals `photoncl render` of
// the same passes bit for bit.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "unit/run_photoncl.h"

namespace fs = std::filesystem;
using photoncl_cli::Result;
using photoncl_cli::run;

namespace {

// A photoncl process whose stderr the test reads line by line.
class Child {
public:
    Child(const std::vector<std::string>& args, const std::string& pause) {
        int fds[2];
        if (::pipe(fds) != 0) return;
        pid_ = ::fork();
        if (pid_ == 0) {
            ::dup2(fds[1], 2);
            ::dup2(fds[1], 1);
            ::close(fds[0]);
            ::close(fds[1]);
            if (!pause.empty()) ::setenv("PHOTONCL_BATCH_TEST_PAUSE", pause.c_str(), 1);
            std::vector<char*> argv;
            std::string bin = PHOTONCL_BINARY;
            argv.push_back(bin.data());
            std::vector<std::string> copy = args;
            for (std::string& a : copy) argv.push_back(a.data());
            argv.push_back(nullptr);
            ::execv(bin.c_str(), argv.data());
            ::_exit(127);
        }
        ::close(fds[1]);
        fd_ = fds[0];
    }
    ~Child() {
        if (pid_ > 0 && !reaped_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
        if (fd_ >= 0) ::close(fd_);
    }
    // Reads output until a line containing `marker` (true) or the end of the output (false).
    bool waitFor(const std::string& marker) {
        char c;
        std::string line;
        while (::read(fd_, &c, 1) == 1) {
            output += c;
            if (c != '\n') {
                line += c;
                continue;
            }
            if (line.find(marker) != std::string::npos) return true;
            line.clear();
        }
        return false;
    }
    void signal(int sig) { ::kill(pid_, sig); }
    // The exit status, or 128 + the signal that ended it.
    int wait() {
        char buf[4096];
        ssize_t n;
        while (fd_ >= 0 && (n = ::read(fd_, buf, sizeof buf)) > 0) output.append(buf, size_t(n));
        int st = 0;
        ::waitpid(pid_, &st, 0);
        reaped_ = true;
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
    std::string output;

private:
    pid_t pid_ = -1;
    int fd_ = -1;
    bool reaped_ = false;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

size_t hiddenTemporaries(const fs::path& folder) {
    size_t n = 0;
    if (fs::exists(folder))
        for (const auto& e : fs::directory_iterator(folder)) n += e.path().filename().string().rfind(".shard-", 0) == 0;
    return n;
}

}  // namespace

TEST(BatchResumeKill, KilledShardsLeaveNothingMergeAcceptsAndAllResumes) {
    const fs::path dir = fs::temp_directory_path() / ("photoncl-batch-kill-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = std::string(PHOTONCL_SOURCE_DIR) + "/scenes/cornell-spheres.json";
    const std::string job = (dir / "job.json").string();
    std::ofstream(job) << R"({"scene": ")" << scene
                       << R"(", "output": "out/img.exr", "passes": 6, "shards": 3, "seed": 2,
        "width": 24, "height": 16, "globalPhotons": 3000, "causticPhotons": 2000, "gatherRays": 4})";
    fs::create_directories(dir / "out");
    const fs::path shards = dir / "out" / "img.exr.shards";
    const fs::path s0 = shards / "shard-0000-of-0003.pcls", s1 = shards / "shard-0001-of-0003.pcls",
                   s2 = shards / "shard-0002-of-0003.pcls";

    // Shard 0 rendered whole.
    Result r = run("batch run " + job + " --shard 0/3 -q");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string shard0 = slurp(s0);
    ASSERT_FALSE(shard0.empty());

    int kills = 0;
    // 1. SIGKILL halfway through writing shard 1's file (half its sums written and fsynced).
    {
        Child c({"batch", "run", job, "--shard", "1/3", "-q"}, "mid-write");
        ASSERT_TRUE(c.waitFor("[batch-test] paused mid-write")) << c.output;
        c.signal(SIGKILL);
        EXPECT_EQ(c.wait(), 128 + SIGKILL);
        ++kills;
        EXPECT_FALSE(fs::exists(s1)) << "a half-written shard under its name";
        EXPECT_EQ(hiddenTemporaries(shards), 1u);  // the half-written temporary, hidden
    }
    // 2. SIGKILL after the temporary is complete and fsynced, before the rename.
    {
        Child c({"batch", "run", job, "--shard", "1/3", "-q"}, "before-rename");
        ASSERT_TRUE(c.waitFor("[batch-test] paused before-rename")) << c.output;
        c.signal(SIGKILL);
        EXPECT_EQ(c.wait(), 128 + SIGKILL);
        ++kills;
        EXPECT_FALSE(fs::exists(s1));
    }
    // 3. SIGKILL in the middle of rendering (after shard 2's first pass).
    {
        Child c({"batch", "run", job, "--shard", "2/3"}, "after-pass");
        ASSERT_TRUE(c.waitFor("[batch-test] paused after-pass")) << c.output;
        c.signal(SIGKILL);
        EXPECT_EQ(c.wait(), 128 + SIGKILL);
        ++kills;
        EXPECT_FALSE(fs::exists(s2));
    }
    // 4. SIGKILL while shard 0 is being rendered again (--force) and about to replace its file:
    // the old file stays whole.
    {
        Child c({"batch", "run", job, "--shard", "0/3", "--force", "-q"}, "before-rename");
        ASSERT_TRUE(c.waitFor("[batch-test] paused before-rename")) << c.output;
        c.signal(SIGKILL);
        EXPECT_EQ(c.wait(), 128 + SIGKILL);
        ++kills;
    }
    EXPECT_EQ(slurp(s0), shard0) << "an earlier shard was damaged";
    r = run("batch merge " + job);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("shard 1 of 3"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("is missing"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "img.exr"));

    // 5. Ctrl-C after shard 2's first pass: the pass ends, an incomplete shard is written, exit 130.
    {
        Child c({"batch", "run", job, "--shard", "2/3"}, "after-pass");
        ASSERT_TRUE(c.waitFor("[batch-test] paused after-pass")) << c.output;
        c.signal(SIGINT);
        EXPECT_EQ(c.wait(), 130) << c.output;
        EXPECT_NE(c.output.find("1 of 2 passes, INCOMPLETE"), std::string::npos) << c.output;
    }
    ASSERT_TRUE(fs::exists(s2));
    // Merge refuses the incomplete shard (and the missing one), naming both.
    r = run("batch merge " + s0.string() + " " + s2.string() + " -o " + (dir / "x.exr").string());
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("incomplete: 1 of 2 passes"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("passes [2, 4) are missing"), std::string::npos) << r.output;

    // 6. --all: shard 0 skipped, shard 1 rendered, shard 2 completed.
    r = run("batch run " + job + " --all");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("shard 0/3: " + s0.string() + " is complete, skipped"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("has 1 of 2 passes; rendering the rest"), std::string::npos) << r.output;
    EXPECT_EQ(slurp(s0), shard0);

    // 7. A damaged shard: refused by merge with its name, rendered again by --all.
    std::string damaged = slurp(s1);
    damaged[damaged.size() / 2] ^= 0x10;
    std::ofstream(s1, std::ios::binary) << damaged;
    r = run("batch merge " + job);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(s1.string() + ": checksum mismatch"), std::string::npos) << r.output;
    r = run("batch run " + job + " --all -q");
    ASSERT_EQ(r.status, 0) << r.output;

    r = run("batch merge " + job);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out" / "img.manifest.json"));
    // The merge equals one `render` of the same passes, bit for bit.
    const std::string single = (dir / "single.exr").string();
    r = run("render " + scene +
            " --width 24 --height 16 --passes 6 --seed 2 --global-photons 3000 --caustic-photons 2000 "
            "--gather-rays 4 -q --no-png -o " +
            single);
    ASSERT_EQ(r.status, 0) << r.output;
    pcl::ImageMetadata mergedMeta, onceMeta;
    pcl::Image merged = pcl::readImage((dir / "out" / "img.exr").string(), &mergedMeta),
               once = pcl::readImage(single, &onceMeta);
    // Both record the same settings text and hash: one serialisation (render/render_settings.h).
    auto extra = [](const pcl::ImageMetadata& m, const std::string& key) {
        for (const auto& [k, v] : m.extra)
            if (k == key) return v;
        return std::string("(missing)");
    };
    EXPECT_NE(extra(onceMeta, "settings"), "(missing)");
    EXPECT_EQ(extra(mergedMeta, "settings"), extra(onceMeta, "settings"));
    EXPECT_EQ(extra(mergedMeta, "settingsHash"), extra(onceMeta, "settingsHash"));
    ASSERT_EQ(merged.rgb.size(), once.rgb.size());
    const bool same = std::memcmp(merged.rgb.data(), once.rgb.data(), once.rgb.size() * sizeof(float)) == 0;
    std::printf("[figure] %d SIGKILLs (mid-render, mid-write, before rename x2) + 1 Ctrl-C + 1 damaged shard, then "
                "--all and merge: %s to one render of the 6 passes\n",
                kills, same ? "bit-identical" : "DIFFERENT");
    EXPECT_TRUE(same);
    fs::remove_all(dir);
}

TEST(BatchPlan, PrintsEveryShardWithItsMemoryAndCalibratedTime) {
    const fs::path dir = fs::temp_directory_path() / ("photoncl-batch-plan-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string job = (dir / "job.json").string();
    std::ofstream(job) << R"({"scene": ")" << PHOTONCL_SOURCE_DIR
                       << R"(/scenes/cornell-spheres.json", "output": "img.exr",
        "passes": 10, "shards": 4, "width": 24, "height": 16, "globalPhotons": 3000, "causticPhotons": 2000})";
    Result r = run("batch plan " + job);
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* row : {"[     0,      2)", "[     2,      5)", "[     5,      7)", "[     7,     10)"})
        EXPECT_NE(r.output.find(row), std::string::npos) << row << "\n" << r.output;
    EXPECT_NE(r.output.find("device: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("host: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("time per pass: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("settings "), std::string::npos) << r.output;
    // A job whose photon map cannot fit under the buffer cap: the plan says so, exit 2.
    std::ofstream(job) << R"({"scene": ")" << PHOTONCL_SOURCE_DIR
                       << R"(/scenes/cornell-spheres.json", "output": "img.exr",
        "passes": 2, "shards": 1, "width": 24, "height": 16, "globalPhotons": 3000000, "maxBufferMib": 8})";
    r = run("batch plan " + job + " --no-calibrate");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("does NOT fit"), std::string::npos) << r.output;
    fs::remove_all(dir);
}
