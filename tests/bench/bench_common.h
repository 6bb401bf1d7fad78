// What every benchmark program shares: the device, the table of rates for the ratios printed
// after the runs, process CPU time, and running the registered benchmarks.
#pragma once

#include <benchmark/benchmark.h>

#include <ctime>
#include <map>
#include <string>

#include "device/device.h"

namespace pcl::bench {

// The device `auto` opens, once per process.
inline Device& device() {
    static Device d = Device::open("auto");
    return d;
}

// A rate per benchmark (its last run), for the ratios printed at the end.
inline std::map<std::string, double>& rates() {
    static std::map<std::string, double> r;
    return r;
}

// CPU seconds of the whole process: every thread, PoCL's workers included.
inline double cpuSeconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

// Registers the benchmarks, then runs those the command line selects.
inline void runBenchmarks(int& argc, char** argv, void (*registerAll)()) {
    registerAll();
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}

}  // namespace pcl::bench
