// Shard files: what one `batch run --shard I/N` rendered, in a form any machine
// can check and merge. Layout (little-endian):
//
//   "PCLSHARD"               8 bytes, magic
//   u32 format version (2), u32 0
//   u64 H, u64 B             header and payload lengths
//   H bytes                  header: JSON (job, shard i of N, passes [first, end) and passes done,
//                            size, seed, scene and settings hashes, settings, program version,
//                            device, photons emitted/stored, seconds by stage, memory)
//   B bytes                  payload: the FixedPointFilm's 128-bit sums (3 per pixel, rows from
//                            the top) then its 128-bit weights (1 per pixel): unnormalised, exact;
//                            each value 16 bytes, its low then its high 64 bits (two's complement)
//                            (version 1 held int64 values; it is refused with both versions named)
//   u64                      FNV-1a 64 of every byte before it
//
// A file is written to a hidden temporary name in the same folder, fsynced, renamed onto its
// name and the folder fsynced, so a process killed at any point (SIGKILL included) leaves either
// the old file or the new one under the name, never a part; the temporary it may leave is hidden
// and never read. A truncated or damaged file fails the length or checksum test with its name.
#pragma once
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "batch/batch_job.h"
#include "image/fixed_point_film.h"

namespace pcl {

struct ShardData {
    std::string job;                 // the job file as given to `batch run`
    uint32_t index = 0, shards = 0;  // shard i of N
    uint32_t passes = 0;             // P: the job's passes, [0, P) over all shards
    PassRange range;                 // global passes [first, end) this shard renders
    uint32_t passesDone = 0;         // passes [first, first + passesDone) are in the sums
    bool complete() const { return passesDone == range.count(); }
    std::string method;
    int width = 0, height = 0;
    uint64_t seed = 0;
    uint64_t sceneHash = 0, settingsHash = 0;
    std::string settings;  // BatchScene::settingsText: what the settings hash covers
    std::string version;   // photoncl version that rendered it
    std::string device, platform, host;
    uint64_t globalEmitted = 0, causticEmitted = 0, globalStored = 0, causticStored = 0;
    uint64_t samples = 0, nonFiniteSamples = 0;
    // Free-form accounting for the manifest: "seconds" by stage, "memory" (device bytes planned
    // and observed, host max RSS), "started"/"finished" UTC times, "runs" (1 + resumes).
    nlohmann::json accounting = nlohmann::json::object();
    FixedPointFilm film;
};

// Writes `shard` to `path` through a temporary (see above). Throws InputError naming `path`.
// PHOTONCL_BATCH_TEST_PAUSE=mid-write|before-rename (tests only) prints
// "[batch-test] paused <where>: <temporary>" on stderr and sleeps 60 s at that point, so a test
// can SIGKILL a real process there.
void writeShardFile(const std::string& path, const ShardData& shard);

// Reads and checks one file: magic, version, lengths (truncation), checksum (damage), header
// fields, payload size. Throws InputError "<path>: <reason>" on any problem.
ShardData readShardFile(const std::string& path);

// The header as JSON (everything but the film), for manifests and `batch plan`.
nlohmann::json shardHeaderJson(const ShardData& shard);

}  // namespace pcl
