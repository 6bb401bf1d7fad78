// One subcommand per file under host/cli/: each add*Command registers its options on the app
// and returns the function that runs it (an exit status, core/error.h: 0 ok, 1 check failed,
// 2 bad input, 3 internal error, 130 interrupted; errors may also be thrown: InputError exits 2,
// any other exception 3).
#pragma once
#include <CLI/CLI.hpp>

#include <functional>

namespace pcl::cli {

using Run = std::function<int()>;

Run addDevicesCommand(CLI::App& app);
Run addRenderCommand(CLI::App& app);
Run addCheckCommand(CLI::App& app);
Run addCompareCommand(CLI::App& app);
Run addAnalyzeCommand(CLI::App& app);
Run addPhotonsCommand(CLI::App& app);
Run addSweepCommand(CLI::App& app);
// `batch` with plan/run/merge (host/cli/batch_command.cpp); it calls addBatchSlurmCommand(*batch)
// (host/cli/batch_slurm_command.cpp) to add `batch slurm`, whose Run is called when that was parsed.
Run addBatchCommand(CLI::App& app);
Run addBatchSlurmCommand(CLI::App& batch);

}  // namespace pcl::cli
