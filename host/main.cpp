// photoncl: the command line. Each subcommand lives in host/cli/<name>_command.cpp; this file
// parses, dispatches, and maps errors onto the exit statuses (core/error.h).
#include <cstdio>
#include <utility>
#include <vector>

#include "cli/command.h"
#include "core/error.h"
#include "device/device.h"

int main(int argc, char** argv) {
    CLI::App app{"photoncl: OpenCL photon-mapping renderer with a CPU twin of every stage.\n"
                 "Exit status: 0 success, 1 a check or comparison failed, 2 bad input (a file, an "
                 "option or a scene's contents), 3 internal error (a device or OpenCL failure, a "
                 "broken internal contract: a bug), 130 a batch shard cut short by Ctrl-C (128 + "
                 "the signal when a second one quits at once).",
                 "photoncl"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("photoncl ") + PHOTONCL_VERSION);

    std::vector<std::pair<CLI::App*, pcl::cli::Run>> commands;
    auto add = [&](pcl::cli::Run run) { commands.emplace_back(app.get_subcommands({}).back(), std::move(run)); };
    add(pcl::cli::addDevicesCommand(app));
    add(pcl::cli::addRenderCommand(app));
    add(pcl::cli::addCheckCommand(app));
    add(pcl::cli::addCompareCommand(app));
    add(pcl::cli::addAnalyzeCommand(app));
    add(pcl::cli::addPhotonsCommand(app));
    add(pcl::cli::addSweepCommand(app));
    add(pcl::cli::addBatchCommand(app));

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return pcl::kExitBadInput;
    }

    pcl::ExitReport report;
    try {
        for (auto& [sub, run] : commands)
            if (sub->parsed()) return run();
        return pcl::kExitBadInput;
    } catch (const cl::Error& e) {
        report = pcl::exitReportFor(pcl::deviceError("unknown stage", e));
    } catch (const std::exception& e) {
        report = pcl::exitReportFor(e);
    }
    std::fprintf(stderr, "photoncl: %s\n", report.message.c_str());
    return report.status;
}
