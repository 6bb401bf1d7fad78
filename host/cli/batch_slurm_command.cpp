// `photoncl batch slurm JOB`: the job's shards as one Slurm job array (one shard per task) and the
// merge as a job that starts once every task succeeded; writes both scripts beside the output,
// submits them with sbatch, prints the job ids. `--dry-run` prints the scripts and the sbatch
// commands and submits nothing. The scripts come from batch/slurm_script (pure, unit-tested).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "batch/batch_job.h"
#include "batch/batch_render.h"
#include "batch/shard_plan.h"
#include "batch/slurm_script.h"
#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "device/device.h"

extern char** environ;

namespace pcl::cli {

namespace {

namespace fs = std::filesystem;

std::string selfExecutable() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec)
        throw InputError(std::string("batch slurm: /proc/self/exe: expected the photoncl binary, got ") + ec.message());
    return exe.string();
}

std::string absolutePath(const std::string& path) { return fs::absolute(fs::path(path)).lexically_normal().string(); }

struct Captured {
    int status = -1;  // exit status, -1 when the program could not start or died by a signal
    std::string out;  // its standard output (standard error passes through)
};

// Runs argv (argv[0] looked up in PATH) and captures its standard output.
Captured runCapturing(const std::vector<std::string>& argv) {
    int pipeFds[2];
    if (pipe(pipeFds) != 0) throw InputError(std::string("batch slurm: pipe: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
    posix_spawn_file_actions_addclose(&actions, pipeFds[1]);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    int err = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipeFds[1]);
    Captured result;
    if (err != 0) {
        close(pipeFds[0]);
        throw InputError("batch slurm: " + argv[0] + ": cannot run it (" + std::strerror(err) +
                         "): expected Slurm's sbatch in PATH (or --sbatch PATH)");
    }
    char buffer[4096];
    ssize_t n;
    while ((n = read(pipeFds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0) result.out.append(buffer, static_cast<size_t>(n));
    close(pipeFds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

// Memory per array task when --mem-mib is left out: `batch plan`'s host estimate for one shard
// (without calibration: films, photon maps read back, the runtime) times 1.5, as the estimate
// leaves out what the driver allocates, rounded up to 64 MiB. 0 (no --mem) when the job's device
// cannot be opened on this machine (a login node without it): the partition's default then.
uint64_t defaultMemPerTaskMib(const BatchJob& job, const std::string& deviceOption) {
    const std::string spec = deviceOption.empty() ? job.device : deviceOption;
    BatchScene scene = loadBatchScene(job);
    std::string why;
    try {
        Device device = Device::open(spec);
        applyBufferCap(device, job.maxBufferMib);
        BatchPlanEstimate e = estimateBatch(scene, device.info(), nullptr);
        const uint64_t mib = (e.hostBytes * 3 / 2 + (1ull << 20) - 1) >> 20;
        const uint64_t rounded = (mib + 63) / 64 * 64;
        std::fprintf(stderr,
                     "batch slurm: --mem %lluM per shard: 1.5x the plan's host estimate (%llu MiB on %s); "
                     "--mem-mib sets it, --mem-mib 0 leaves it to the partition\n",
                     static_cast<unsigned long long>(rounded), static_cast<unsigned long long>(e.hostBytes >> 20),
                     device.info().name.c_str());
        return rounded;
    } catch (const DeviceError& e) {
        why = e.what();
    } catch (const cl::Error& e) {
        why = deviceError("batch slurm", e).what();
    }
    std::fprintf(stderr,
                 "batch slurm: no --mem (device \"%s\" cannot be opened here to plan for: %s); --mem-mib sets it\n",
                 spec.c_str(), why.c_str());
    return 0;
}

// Submits argv; returns the job id sbatch --parsable printed.
std::string submit(std::vector<std::string> argv, const std::string& sbatch, const std::string& what) {
    argv[0] = sbatch;
    Captured c = runCapturing(argv);
    if (c.status != 0)
        throw InputError("batch slurm: submitting the " + what + " failed: `" + shellCommandLine(argv) +
                         "` exited with " + std::to_string(c.status) + " (its message is above)");
    return parseSbatchJobId(c.out);
}

}  // namespace

Run addBatchSlurmCommand(CLI::App& batch) {
    struct Options {
        std::string job, partition, time, device, logDir, jobName, sbatch = "sbatch";
        int64_t memMib = -1;  // -1: from the plan
        uint32_t cpus = 0, maxRunning = 0;
        std::vector<std::string> sbatchArgs;
        bool dryRun = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* sub = batch.add_subcommand("slurm",
                                         "Submit the job to Slurm: the shards as one job array (`batch run JOB --shard "
                                         "$SLURM_ARRAY_TASK_ID/N`), the merge as a job after every task succeeded");
    sub->add_option("JOB", o->job, "Job file (JSON)")->required();
    sub->add_flag("--dry-run", o->dryRun, "Print the two scripts and the sbatch commands; submit nothing");
    sub->add_option("--partition", o->partition, "Slurm partition (default: the cluster's)");
    sub->add_option("--time", o->time, "Time limit per job, sbatch's format (e.g. 30, 2:00:00)");
    sub->add_option("--mem-mib", o->memMib,
                    "Memory per array task in MiB (sbatch --mem); default 1.5x `batch plan`'s host estimate; 0: "
                    "no --mem (the partition's default)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--cpus-per-task", o->cpus, "CPUs per array task (sbatch --cpus-per-task)");
    sub->add_option("--max-running", o->maxRunning, "At most this many shards at once (--array=0-N%M)");
    sub->add_option("--device", o->device, "Device for every shard (`batch run --device`; default: the job's)");
    sub->add_option("--job-name", o->jobName, "Name of the array job (default: photoncl-<job file name>)");
    sub->add_option("--log-dir", o->logDir, "Folder for the scripts and logs (default: <output>.slurm)");
    sub->add_option("--sbatch-arg", o->sbatchArgs,
                    "Extra argument for both sbatch calls, e.g. --sbatch-arg=--account=render")
        ->allow_extra_args(false);
    sub->add_option("--sbatch", o->sbatch, "The sbatch program (default: sbatch in PATH)");
    return [o] {
        BatchJob job = loadBatchJob(o->job);
        SlurmSubmission s;
        s.photoncl = selfExecutable();
        s.jobFile = absolutePath(o->job);
        s.shards = job.shards;
        s.jobName = o->jobName.empty() ? "photoncl-" + fs::path(o->job).stem().string() : o->jobName;
        s.logDir = absolutePath(o->logDir.empty() ? job.output + ".slurm" : o->logDir);
        s.partition = o->partition;
        s.timeLimit = o->time;
        s.memPerTaskMib = o->memMib >= 0 ? uint64_t(o->memMib) : defaultMemPerTaskMib(job, o->device);
        s.cpusPerTask = o->cpus;
        s.maxRunning = o->maxRunning;
        s.device = o->device;
        std::string shardScript = slurmShardScript(s), mergeScript = slurmMergeScript(s);
        std::vector<std::string> shardCommand = sbatchShardCommand(s, o->sbatchArgs);

        if (o->dryRun) {
            std::printf("#### %s\n%s#### %s\n%s", slurmShardScriptPath(s).c_str(), shardScript.c_str(),
                        slurmMergeScriptPath(s).c_str(), mergeScript.c_str());
            std::printf("#### submit (JOBID: the id the first sbatch prints)\n%s\n%s\n",
                        shellCommandLine(shardCommand).c_str(),
                        shellCommandLine(sbatchMergeCommand(s, "JOBID", o->sbatchArgs)).c_str());
            return kExitOk;
        }

        fs::create_directories(s.logDir);
        writeFileAtomically(slurmShardScriptPath(s), shardScript);
        writeFileAtomically(slurmMergeScriptPath(s), mergeScript);
        std::string shardsId = submit(shardCommand, o->sbatch, "shards (job array)");
        std::string mergeId;
        try {
            mergeId = submit(sbatchMergeCommand(s, shardsId, o->sbatchArgs), o->sbatch, "merge");
        } catch (const InputError&) {
            std::fprintf(stderr, "photoncl: the shards were submitted as job %s; `scancel %s` cancels them\n",
                         shardsId.c_str(), shardsId.c_str());
            throw;
        }
        std::printf("shards: job %s, array 0-%u, logs %s/shard-<task>.log\n", shardsId.c_str(), s.shards - 1,
                    s.logDir.c_str());
        std::printf("merge: job %s, after job %s succeeds, log %s/merge.log, writes %s\n", mergeId.c_str(),
                    shardsId.c_str(), s.logDir.c_str(), absolutePath(job.output).c_str());
        return kExitOk;
    };
}

}  // namespace pcl::cli
