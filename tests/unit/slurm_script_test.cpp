// The Slurm scripts of `photoncl batch slurm` (batch/slurm_script): array range, dependency,
// absolute photoncl and job paths, and quoting of paths with spaces and quotes, checked by running
// the generated script's command with bash against a stand-in photoncl that prints its arguments.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "batch/slurm_script.h"
#include "core/error.h"

namespace fs = std::filesystem;
using namespace pcl;

namespace {

SlurmSubmission submission() {
    SlurmSubmission s;
    s.photoncl = "/opt/photoncl/bin/photoncl";
    s.jobFile = "/data/jobs/cornell.json";
    s.shards = 4;
    s.jobName = "photoncl-cornell";
    s.logDir = "/data/out/cornell.exr.slurm";
    return s;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// `bash -c SCRIPT` with an environment prefix; its stdout and exit status.
std::pair<int, std::string> bash(const std::string& scriptPath, const std::string& env) {
    std::string cmd = env + " bash " + shellQuote(scriptPath) + " 2>&1";
    std::string out;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, out};
    std::array<char, 4096> buf;
    while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
    int raw = pclose(pipe);
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out};
}

}  // namespace

TEST(SlurmScript, ShardScriptIsAnArrayOfOneShardPerTask) {
    SlurmSubmission s = submission();
    std::string script = slurmShardScript(s);
    std::printf("%s", script.c_str());
    EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
    EXPECT_TRUE(contains(script, "\n#SBATCH --array=0-3\n"));
    EXPECT_TRUE(contains(script, "\n#SBATCH --job-name=photoncl-cornell\n"));
    // One log per task: %a is the array index; the path is double-quoted for sbatch.
    EXPECT_TRUE(contains(script, "\n#SBATCH --output=\"/data/out/cornell.exr.slurm/shard-%a.log\"\n"));
    EXPECT_TRUE(contains(
        script,
        "\nexec /opt/photoncl/bin/photoncl batch run /data/jobs/cornell.json --shard \"${SLURM_ARRAY_TASK_ID}/4\"\n"));
    // Options left out write no directive.
    for (const char* absent : {"--partition", "--time", "--mem", "--cpus-per-task", "--device", "%2"})
        EXPECT_FALSE(contains(script, absent)) << absent;

    s.shards = 1;
    EXPECT_TRUE(contains(slurmShardScript(s), "\n#SBATCH --array=0-0\n"));
    s.shards = 1000;
    EXPECT_TRUE(contains(slurmShardScript(s), "\n#SBATCH --array=0-999\n"));
    EXPECT_TRUE(contains(slurmShardScript(s), "--shard \"${SLURM_ARRAY_TASK_ID}/1000\""));
}

TEST(SlurmScript, OptionsBecomeDirectives) {
    SlurmSubmission s = submission();
    s.partition = "render";
    s.timeLimit = "2:00:00";
    s.memPerTaskMib = 3072;
    s.cpusPerTask = 8;
    s.maxRunning = 2;
    s.device = "gpu";
    std::string shards = slurmShardScript(s), merge = slurmMergeScript(s);
    EXPECT_TRUE(contains(shards, "\n#SBATCH --array=0-3%2\n"));
    EXPECT_TRUE(contains(shards, "\n#SBATCH --partition=render\n"));
    EXPECT_TRUE(contains(shards, "\n#SBATCH --time=2:00:00\n"));
    EXPECT_TRUE(contains(shards, "\n#SBATCH --mem=3072M\n"));
    EXPECT_TRUE(contains(shards, "\n#SBATCH --cpus-per-task=8\n"));
    EXPECT_TRUE(contains(shards, "--shard \"${SLURM_ARRAY_TASK_ID}/4\" --device gpu\n"));
    // The merge shares partition and time, not the per-task resources.
    EXPECT_TRUE(contains(merge, "\n#SBATCH --partition=render\n"));
    EXPECT_TRUE(contains(merge, "\n#SBATCH --time=2:00:00\n"));
    EXPECT_FALSE(contains(merge, "--mem"));
    EXPECT_FALSE(contains(merge, "--array"));
}

TEST(SlurmScript, MergeRunsAfterEveryTaskSucceeded) {
    SlurmSubmission s = submission();
    std::string merge = slurmMergeScript(s);
    std::printf("%s", merge.c_str());
    EXPECT_TRUE(contains(merge, "\n#SBATCH --job-name=photoncl-cornell-merge\n"));
    EXPECT_TRUE(contains(merge, "\n#SBATCH --output=\"/data/out/cornell.exr.slurm/merge.log\"\n"));
    EXPECT_TRUE(contains(merge, "\nexec /opt/photoncl/bin/photoncl batch merge /data/jobs/cornell.json\n"));

    std::vector<std::string> first = sbatchShardCommand(s, {"--account=render"});
    EXPECT_EQ(shellCommandLine(first), "sbatch --parsable --account=render /data/out/cornell.exr.slurm/shards.sbatch");
    std::vector<std::string> second = sbatchMergeCommand(s, "4711", {"--account=render"});
    EXPECT_EQ(shellCommandLine(second),
              "sbatch --parsable --dependency=afterok:4711 --kill-on-invalid-dep=yes --account=render "
              "/data/out/cornell.exr.slurm/merge.sbatch");
}

TEST(SlurmScript, ParsesSbatchParsableAnswers) {
    EXPECT_EQ(parseSbatchJobId("4711\n"), "4711");
    EXPECT_EQ(parseSbatchJobId("4711;cluster-a\n"), "4711");
    EXPECT_EQ(parseSbatchJobId("sbatch: warning: something odd\n4712\n"), "4712");
    EXPECT_THROW(parseSbatchJobId(""), InputError);
    EXPECT_THROW(parseSbatchJobId("sbatch: error: Batch job submission failed\n"), InputError);
}

TEST(SlurmScript, RefusesWhatWouldBreakTheScript) {
    SlurmSubmission s = submission();
    s.shards = 0;
    EXPECT_THROW(slurmShardScript(s), InputError);
    s = submission();
    s.jobFile = "jobs/cornell.json";  // relative: the task runs elsewhere
    EXPECT_THROW(slurmShardScript(s), InputError);
    s = submission();
    s.logDir = "/data/out\n#SBATCH --x";
    EXPECT_THROW(slurmShardScript(s), InputError);
    s = submission();
    s.partition = "a b";
    EXPECT_THROW(slurmMergeScript(s), InputError);
    s = submission();
    s.jobName = "";
    EXPECT_THROW(slurmShardScript(s), InputError);
}

TEST(SlurmScript, ShellQuoting) {
    EXPECT_EQ(shellQuote("/usr/bin/photoncl"), "/usr/bin/photoncl");
    EXPECT_EQ(shellQuote("/my renders/job.json"), "'/my renders/job.json'");
    EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
    EXPECT_EQ(shellQuote("$HOME"), "'$HOME'");
    EXPECT_EQ(shellQuote(""), "''");
}

// The generated shard and merge scripts, run by bash as Slurm would, hand photoncl exactly the
// paths given (spaces, a quote, a dollar sign) and the task's shard.
TEST(SlurmScript, PathsWithSpacesReachPhotonclIntact) {
    fs::path dir = fs::temp_directory_path() / ("photoncl slurm 'q' $x " + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::path fake = dir / "photon cl";
    {
        std::ofstream f(fake);
        f << "#!/bin/bash\nfor a in \"$0\" \"$@\"; do printf '<%s>\\n' \"$a\"; done\n";
    }
    fs::permissions(fake, fs::perms::owner_all);

    SlurmSubmission s = submission();
    s.photoncl = fake.string();
    s.jobFile = (dir / "my job.json").string();
    s.logDir = (dir / "logs 50%").string();
    s.shards = 3;
    s.device = "NVIDIA H100";
    fs::path shardScript = dir / "shards.sbatch", mergeScript = dir / "merge.sbatch";
    std::ofstream(shardScript) << slurmShardScript(s);
    std::ofstream(mergeScript) << slurmMergeScript(s);

    auto [status, out] = bash(shardScript.string(), "SLURM_ARRAY_TASK_ID=2");
    std::printf("%s", out.c_str());
    EXPECT_EQ(status, 0);
    EXPECT_EQ(out, "<" + fake.string() + ">\n<batch>\n<run>\n<" + s.jobFile +
                       ">\n<--shard>\n<2/3>\n<--device>\n<NVIDIA H100>\n");
    // A literal % in a log path is %% for sbatch's filename patterns.
    EXPECT_TRUE(contains(slurmShardScript(s), "logs 50%%/shard-%a.log\""));

    auto [mergeStatus, mergeOut] = bash(mergeScript.string(), "");
    EXPECT_EQ(mergeStatus, 0);
    EXPECT_EQ(mergeOut, "<" + fake.string() + ">\n<batch>\n<merge>\n<" + s.jobFile + ">\n");

    // Without the array task id the script fails instead of running a wrong shard (set -u).
    auto [unsetStatus, unsetOut] = bash(shardScript.string(), "env -u SLURM_ARRAY_TASK_ID");
    EXPECT_NE(unsetStatus, 0);
    fs::remove_all(dir);
}
