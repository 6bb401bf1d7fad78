// Error types that map onto the command line's exit statuses (README.md, "Commands";
// exitReportFor below): 0 success, 1 a check failed, 2 bad input, 3 internal error.
#pragma once
#include <exception>
#include <stdexcept>
#include <string>

namespace pcl {

// Bad input: what the user supplied (a scene, job or image file, an option, a scene's contents,
// a device too small for the render asked for). The message names the file, the field, what was
// found and what was expected, e.g. "scenes/x.json: materials[2].rho_d: expected 3 numbers in
// [0,1], got [1.2,0,0]". Exit status 2.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// An OpenCL failure: no device, build error, launch error. Carries the stage name. Exit status 3.
struct DeviceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A broken contract inside photoncl: a function given arguments its callers never pass for any
// input (what the user supplies is checked before it gets there). A bug. Exit status 3.
struct InternalError : std::logic_error {
    using std::logic_error::logic_error;
};

enum ExitStatus : int {
    kExitOk = 0,
    kExitCheckFailed = 1,    // a check or comparison ran and failed
    kExitBadInput = 2,       // InputError, or options the parser refused
    kExitInternal = 3,       // InternalError, DeviceError, an OpenCL error, any other exception
    kExitInterrupted = 130,  // 128 + SIGINT: a batch shard cut short by Ctrl-C (128 + the signal
                             // when a second signal quits at once)
};

// What the command line prints ("photoncl: " + message) and returns for the exception that ended
// a command.
struct ExitReport {
    int status = kExitInternal;
    std::string message;
};
ExitReport exitReportFor(const std::exception& e);

}  // namespace pcl
