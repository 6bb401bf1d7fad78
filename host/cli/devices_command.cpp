#include <iostream>

#include "cli/command.h"
#include "device/device.h"

namespace pcl::cli {

Run addDevicesCommand(CLI::App& app) {
    app.add_subcommand("devices", "List OpenCL platforms and devices (the indices --device takes)");
    return [] {
        printDevices(std::cout);
        return 0;
    };
}

}  // namespace pcl::cli
