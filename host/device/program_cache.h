// ProgramCache: kernel sources → built cl::Programs, with compiled binaries kept on disk.
//
// Sources come from the binary (kEmbeddedKernels) or, when PHOTONCL_KERNEL_DIR is set, from
// <dir>/<stage>.cl with `#include "shared/…"` expanded exactly as scripts/embed_kernels.py does
// (with #line markers, so a build log points at the real file and line).
//
// Binaries live in cacheDirectory() as <stage>-<key>.bin, where key is the FNV-1a 64-bit hash
// (core/hash.h) of the length-prefixed fields (expanded source,
// build options, platform version, device name, driver version). FNV-1a is no cryptographic
// hash, but the cache only has to tell our own builds apart, and a collision still has to pass
// the device's own binary check. Each file is a 24-byte header {magic "PCLBIN01", binary
// length, FNV-1a 64 of the binary} and the binary; it is written to a temporary name and renamed,
// so readers see a whole file or none. A file whose header, length or checksum is wrong, or
// that the device refuses, is deleted and the program rebuilt from source. Every kernel edit
// makes a new key, so each stage keeps only its most recently used entries (a hit refreshes
// the file's time) and older ones are deleted when a new one is stored.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "core/hash.h"
#include "device/device.h"

namespace pcl {

// No fast-math options by default: the kernels are cross-checked against CPU twins, and
// -cl-mad-enable / -cl-fast-relaxed-math would change results bit for bit.
inline constexpr const char* kDefaultBuildOptions = "-cl-std=CL1.2";

// $PHOTONCL_CACHE_DIR, else $XDG_CACHE_HOME/photoncl, else $HOME/.cache/photoncl.
std::filesystem::path cacheDirectory();

// $PHOTONCL_KERNEL_DIR when set and non-empty.
std::optional<std::filesystem::path> kernelDirOverride();

// kernels/<stage>.cl under kernelDir with its includes expanded (throws DeviceError if the
// file or an include is missing).
std::string expandKernelFile(const std::filesystem::path& kernelDir, const std::string& stage);

// The expanded source of a stage: from kernelDir when given, else embedded.
// Throws DeviceError for an unknown stage.
std::string kernelSource(const std::string& stage, const std::optional<std::filesystem::path>& kernelDir);

// A build log with the compiler's own line numbers in the expanded source ("<kernel>:6:12:", as
// NVIDIA's OpenCL writes them, ignoring #line) replaced by the file and line the source's #line
// markers give ("broken.cl:3:12:"). Logs that already name files pass through unchanged.
std::string mapBuildLogLines(const std::string& log, const std::string& source);

class ProgramCache {
public:
    // kernelDir: where sources are read from (nullopt: the embedded ones).
    // cacheDir: where binaries are kept (nullopt: no disk cache).
    ProgramCache(cl::Context context, DeviceInfo device,
                 std::optional<std::filesystem::path> kernelDir = kernelDirOverride(),
                 std::optional<std::filesystem::path> cacheDir = cacheDirectory());

    // Builds kernels/<stage>.cl with kDefaultBuildOptions + options. Not memoised: Device does
    // that. Throws DeviceError on a build failure (file, device, options, log).
    cl::Program build(const std::string& stage, const std::string& options = "");

    // What the last builds did, for tests and `--verbose` timing.
    struct Stats {
        int compiled = 0;        // built from source (cache miss or no cache)
        int loaded = 0;          // built from a cached binary
        int rejected = 0;        // cache entries found corrupt or refused by the device, deleted
        double lastSeconds = 0;  // wall time of the last build()
    };
    const Stats& stats() const { return stats_; }

    // How many binaries of one stage the disk cache keeps (all options and sources together).
    void setMaxEntriesPerStage(size_t n) { maxEntriesPerStage_ = n; }

    // The cache file a (stage, options) build uses; empty when there is no disk cache.
    std::filesystem::path entryPath(const std::string& stage, const std::string& options = "") const;

private:
    std::string fullOptions(const std::string& options) const;
    std::optional<cl::Program> loadBinary(const std::filesystem::path& file, const std::string& options);
    void storeBinary(const std::filesystem::path& file, const cl::Program& program);
    void prune(const std::string& stage, const std::filesystem::path& keep);
    std::filesystem::path entryPathFor(const std::string& stage, const std::string& source,
                                       const std::string& options) const;

    cl::Context context_;
    DeviceInfo device_;
    std::optional<std::filesystem::path> kernelDir_, cacheDir_;
    Stats stats_;
    size_t maxEntriesPerStage_ = 32;
};

}  // namespace pcl
