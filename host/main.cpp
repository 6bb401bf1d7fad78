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
                 "Exit status: 0 success, 1 a check or comparison failed, 2 bad input or options, "
                 "3 device failure.",
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

    try {
        for (auto& [sub, run] : commands)
            if (sub->parsed()) return run();
    } catch (const pcl::InputError& e) {
        std::fprintf(stderr, "photoncl: %s\n", e.what());
        return pcl::kExitBadInput;
    } catch (const pcl::DeviceError& e) {
        std::fprintf(stderr, "photoncl: device error: %s\n", e.what());
        return pcl::kExitDevice;
    } catch (const cl::Error& e) {
        std::fprintf(stderr, "photoncl: device error: %s\n", pcl::deviceError("unknown stage", e).what());
        return pcl::kExitDevice;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "photoncl: internal error: %s\n", e.what());
        return pcl::kExitCheckFailed;
    }
    return pcl::kExitBadInput;
}
