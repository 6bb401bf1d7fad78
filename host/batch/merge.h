// Merging shards: every shard file checked (checksum, scene and settings hashes,
// program version, size, pass ranges), the mismatched, duplicated, overlapping, missing,
// incomplete and corrupt ones refused with one message naming each file and why, then the
// fixed-point sums added in order of their first pass (integer sums: any order gives the same
// bits) and resolved into the final image, with a manifest of every shard.
//
// Incomplete shards (interrupted by Ctrl-C: fewer passes done than their range) are refused
// unless allowPartial: `batch run JOB --all` completes them. With allowPartial the image is the
// average of the passes done, the manifest says which passes are missing and the merge still
// refuses overlaps, mismatches and damage.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/shard_file.h"
#include "image/fixed_point_film.h"

namespace pcl {

// What every shard must agree with (from the job: loadBatchScene); a field left 0 / empty is
// taken from the first shard instead (merging a list of files without their job).
struct MergeExpectation {
    uint64_t sceneHash = 0, settingsHash = 0;
    std::string settings;  // settings text, to name the keys that differ
    uint32_t passes = 0;   // P: the shards' ranges must tile [0, P) exactly
    int width = 0, height = 0;
};

struct MergeOptions {
    bool allowPartial = false;
};

struct MergedShards {
    FixedPointFilm film;
    std::vector<std::string> files;    // in the order added (by first pass)
    std::vector<ShardData> shards;     // headers (films dropped after adding)
    uint32_t passesDone = 0;           // passes in the sums
    uint32_t passes = 0;               // P
    bool partial = false;              // some passes missing (allowPartial)
    std::vector<std::string> devices;  // distinct devices, in order of appearance
};

// Reads, checks and adds `files`. Throws InputError listing every problem found.
MergedShards mergeShardFiles(const std::vector<std::string>& files, const MergeExpectation& expect,
                             const MergeOptions& options);

// The manifest: the job, the image files, the hashes and settings, every shard (file, passes,
// device, host, version, runs with seconds by stage and memory) and totals (seconds by stage,
// the largest host RSS and device bytes of any shard), and the devices used.
nlohmann::json mergeManifest(const MergedShards& merged, const std::string& job, const std::string& scene,
                             const std::string& image, double mergeSeconds);

// "a;b;c" settings texts: the keys whose values differ, "passes 8 vs 16, seed 0 vs 1".
std::string settingsDifference(const std::string& a, const std::string& b);

}  // namespace pcl
