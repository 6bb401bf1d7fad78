// The one Device every stage test in this process shares, so each program is built once per
// process. PHOTONCL_TEST_DEVICE picks it (default "auto"). There is no skip: CI always has
// PoCL, and a machine without any OpenCL device fails every device test with the reason.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include <unistd.h>

#include "device/device.h"

namespace pcl::test {

inline Device& testDevice() {
    static Device device = [] {
        const char* spec = std::getenv("PHOTONCL_TEST_DEVICE");
        return Device::open(spec && *spec ? spec : "auto");
    }();
    return device;
}

// A fresh empty directory under the system temp dir, removed when the object goes.
class TempDir {
public:
    TempDir() {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() /
                ("photoncl-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace pcl::test
