// Ctrl-C (SIGINT) and a scheduler's cancel (SIGTERM, as Slurm sends) for the long commands
// (render, batch run): the work stops between passes and what is done is written.
//
// The signals are blocked in every thread and taken by one sigwait thread instead of a handler:
// a terminal's Ctrl-C goes to the whole process group, and PoCL links kernels in forked linker
// processes, which inherit the blocked mask across exec and so are not killed halfway (that
// aborted PoCL). Call it before the OpenCL device is opened: threads created later inherit the
// mask.
#pragma once
#include <atomic>

namespace pcl {

// Starts the watcher (once per process) and returns the stop flag, cleared. graceful: the first
// signal sets the flag; another more than a second later exits at once with 128 + the signal
// (one interrupt can arrive twice: timeout(1) signals the process and then its group, so signals
// within a second of the first count as one). Not graceful (work that cannot stop between
// passes): the first signal exits.
const std::atomic<bool>& watchInterrupts(bool graceful);

}  // namespace pcl
