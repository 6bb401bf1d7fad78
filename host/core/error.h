// Error types that map onto the command line's exit statuses (README.md, "Commands": 1 check failed,
// 2 bad input or options, 3 device failure).
#pragma once
#include <stdexcept>
#include <string>

namespace pcl {

// Bad input: a scene, job or option. The message names the file, the field, what was found
// and what was expected, e.g. "scenes/x.json: materials[2].rho_d: expected 3 numbers in [0,1], got [1.2,0,0]".
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// An OpenCL failure: no device, build error, launch error. Carries the stage name.
struct DeviceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum ExitStatus : int { kExitOk = 0, kExitCheckFailed = 1, kExitBadInput = 2, kExitDevice = 3 };

}  // namespace pcl
