// Slurm scripts for a batch job: the shards as one job array, one shard per array task
// (`photoncl batch run JOB --shard $SLURM_ARRAY_TASK_ID/N`), and the merge as a second job that
// Slurm starts only after every task of the array succeeded (`--dependency=afterok:<array id>`).
// Pure functions of their inputs: `photoncl batch slurm` writes the scripts, submits them with
// sbatch and parses its `--parsable` answers; `--dry-run` prints them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {

struct SlurmSubmission {
    std::string photoncl;        // absolute path of the photoncl binary the tasks run
    std::string jobFile;         // absolute path of the job file
    uint32_t shards = 1;         // N: array tasks 0..N-1
    std::string jobName;         // the array's name; the merge job's is "<name>-merge"
    std::string logDir;          // absolute folder for the scripts and the logs
    std::string partition;       // empty: the cluster's default partition
    std::string timeLimit;       // sbatch --time per task, e.g. "30" or "1:00:00"; empty: the partition's
    uint64_t memPerTaskMib = 0;  // sbatch --mem of each array task; 0: the partition's default
    uint32_t cpusPerTask = 0;    // sbatch --cpus-per-task of each array task; 0: the default (1)
    uint32_t maxRunning = 0;     // at most this many tasks at once (--array=0-3%M); 0: no limit
    std::string device;          // `batch run --device`; empty: the job's device
};

// Checks what would make a broken script (N = 0, relative paths, a newline in a path, spaces in
// options that go on #SBATCH lines); throws InputError naming the option.
void checkSlurmSubmission(const SlurmSubmission& s);

// The array job's script: #SBATCH --array=0-(N-1), the job name, a log per task
// (logDir/shard-<task>.log), then `exec photoncl batch run JOB --shard $SLURM_ARRAY_TASK_ID/N`.
std::string slurmShardScript(const SlurmSubmission& s);
// The merge job's script: log logDir/merge.log, then `exec photoncl batch merge JOB`.
std::string slurmMergeScript(const SlurmSubmission& s);

// Where batch slurm writes the two scripts (inside logDir).
std::string slurmShardScriptPath(const SlurmSubmission& s);
std::string slurmMergeScriptPath(const SlurmSubmission& s);

// The sbatch command lines (argv): the array, and the merge after the array's job id.
// `extraArgs` go to both, before the script, as given (e.g. "--account=render").
std::vector<std::string> sbatchShardCommand(const SlurmSubmission& s, const std::vector<std::string>& extraArgs);
std::vector<std::string> sbatchMergeCommand(const SlurmSubmission& s, const std::string& shardJobId,
                                            const std::vector<std::string>& extraArgs);

// The job id in sbatch --parsable's answer ("12345" or "12345;cluster", newline-terminated);
// throws InputError when there is none.
std::string parseSbatchJobId(const std::string& parsableOutput);

// A word the shell reads back as exactly `word`: left bare when made of safe characters, else in
// single quotes ('it'\''s').
std::string shellQuote(const std::string& word);
// argv as one shell command line, each word quoted as needed.
std::string shellCommandLine(const std::vector<std::string>& argv);

}  // namespace pcl
