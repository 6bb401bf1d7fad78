// `photoncl batch plan|run|merge JOB`: one render split into shards of passes that any
// machine renders independently and that merge into exactly the image one run of all the passes
// gives on that device (README, "Batch renders"; host/batch/).
//   plan   the shards' pass ranges and the memory and time each is expected to take
//   run    --shard I/N renders shard I; --all renders every shard missing, damaged or incomplete
//   merge  checks every shard and writes the image (EXR + PNG) and a manifest
// `batch slurm` comes from host/cli/batch_slurm_command.cpp (addBatchSlurmCommand).
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "batch/batch_job.h"
#include "batch/batch_render.h"
#include "batch/merge.h"
#include "batch/shard_file.h"
#include "batch/shard_plan.h"
#include "cli/command.h"
#include "cli/memory_option.h"
#include "core/atomic_file.h"
#include "core/clock.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "device/device.h"
#include "image/image_io.h"

namespace fs = std::filesystem;

namespace pcl::cli {
namespace {

// Ctrl-C (or a scheduler's SIGTERM; core/interrupt.h): the shard finishes its pass and is
// written as a partial shard; a second signal a second later quits.
const std::atomic<bool>* gStop = nullptr;

// PHOTONCL_BATCH_TEST_PAUSE=after-pass (tests only): after each pass, say so and wait (up to 60 s)
// for a stop request, so a test can Ctrl-C a real process between passes deterministically.
void pauseAfterPassIfAsked(uint32_t shard, uint32_t done) {
    const char* v = std::getenv("PHOTONCL_BATCH_TEST_PAUSE");
    if (!v || std::strcmp(v, "after-pass") != 0) return;
    std::fprintf(stderr, "[batch-test] paused after-pass: shard %u, %u pass(es) done\n", shard, done);
    std::fflush(stderr);
    for (int i = 0; i < 6000 && !gStop->load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

struct BatchOptions {
    std::string job, shard, device, output;
    std::vector<std::string> inputs;
    bool all = false, force = false, quiet = false, noCalibrate = false, allowPartial = false, noPng = false;
};

// The OpenCL device of a photon-mapping job; none for the path tracer (the CPU reference),
// which accepts only --device ref, cpu or auto, as `render --method path` does.
std::unique_ptr<Device> openDevice(const BatchOptions& o, const BatchJob& job) {
    std::string spec = o.device.empty() ? job.device : o.device;
    if (job.method == "path") {
        if (spec != "ref" && spec != "cpu" && spec != "auto")
            throw InputError("batch: method path runs on the CPU reference (--device ref); got --device " + spec);
        return nullptr;
    }
    if (spec == "ref")
        throw InputError("batch: --device ref (the CPU reference) renders only method path; the job's method is " +
                         job.method);
    auto device = std::make_unique<Device>(Device::open(spec));
    applyBufferCap(*device, job.maxBufferMib);
    return device;
}

int runPlan(const BatchOptions& o) {
    BatchJob job = loadBatchJob(o.job);
    BatchScene scene = loadBatchScene(job);
    std::unique_ptr<Device> device = openDevice(o, job);
    DeviceInfo info;
    if (device) info = device->info();
    else info.name = kPathTracerDevice;
    if (!o.noCalibrate && !o.quiet)
        std::fprintf(stderr, "calibrating: one pass of the job, twice, on %s ...\n", info.name.c_str());
    BatchPlanEstimate e = estimateBatch(scene, info, device.get(), !o.noCalibrate, job.threads);
    std::fputs(formatBatchPlan(scene, e).c_str(), stdout);
    return e.memoryProblems.empty() ? kExitOk : kExitBadInput;
}

// Why the file at `path` cannot stand as shard i of the job ("" if it can), and the shard if
// it is readable and matches (complete or not).
std::string checkExisting(const std::string& path, const BatchScene& bs, uint32_t i, ShardData& shard) {
    try {
        shard = readShardFile(path);
    } catch (const InputError& e) {
        return e.what();
    }
    const PassRange r = shardPasses(bs.job, i);
    if (shard.sceneHash != bs.sceneHash) return "rendered from another scene (the scene changed)";
    if (shard.settingsHash != bs.settingsHash)
        return "rendered with other settings (" + settingsDifference(bs.settingsText, shard.settings) + ")";
    if (shard.index != i || shard.shards != bs.job.shards || shard.range.first != r.first || shard.range.end != r.end)
        return "holds another shard (" + std::to_string(shard.index) + " of " + std::to_string(shard.shards) + ")";
    if (shard.version != PHOTONCL_VERSION) return "rendered by photoncl " + shard.version;
    return "";
}

// Renders shard i (resuming a partial one); false if interrupted.
bool renderOne(Device* device, const BatchScene& bs, uint32_t i, bool force, bool quiet, double& loadSeconds) {
    const BatchJob& job = bs.job;
    const std::string path = shardPath(job, i);
    const PassRange range = shardPasses(job, i);
    ShardData existing;
    const ShardData* resume = nullptr;
    if (fs::exists(path) && !force) {
        std::string why = checkExisting(path, bs, i, existing);
        if (why.empty() && existing.complete()) {
            if (!quiet) std::fprintf(stderr, "shard %u/%u: %s is complete, skipped\n", i, job.shards, path.c_str());
            return true;
        }
        if (why.empty()) {
            resume = &existing;
            if (!quiet)
                std::fprintf(stderr, "shard %u/%u: %s has %u of %u passes; rendering the rest\n", i, job.shards,
                             path.c_str(), existing.passesDone, range.count());
        } else if (!quiet) {
            std::fprintf(stderr, "shard %u/%u: %s is not usable (%s); rendering it again\n", i, job.shards,
                         path.c_str(), why.c_str());
        }
    }
    if (!quiet)
        std::fprintf(stderr, "shard %u/%u: passes [%u, %u) on %s\n", i, job.shards, range.first, range.end,
                     device ? device->info().name.c_str() : kPathTracerDevice);
    auto start = std::chrono::steady_clock::now();
    ShardRunOptions ro;
    ro.stop = gStop;
    ro.loadSeconds = loadSeconds;  // counted once, for the first shard this process renders
    ro.threads = job.threads;
    loadSeconds = 0;
    ro.onPass = [&](uint32_t done, uint32_t total) {
        if (!quiet) {
            double s = since(start);
            std::fprintf(stderr, "shard %u/%u: %u of %u passes, %.1fs\n", i, job.shards, done, total, s);
        }
        pauseAfterPassIfAsked(i, done);
    };
    ShardData shard = renderShard(device, bs, i, range, resume, ro);
    fs::create_directories(shardFolder(job));
    writeShardFile(path, shard);
    if (!quiet)
        std::fprintf(stderr, "shard %u/%u: wrote %s (%u of %u passes%s)\n", i, job.shards, path.c_str(),
                     shard.passesDone, range.count(),
                     shard.complete() ? "" : ", INCOMPLETE: interrupted; `batch run JOB --all` completes it");
    if (shard.nonFiniteSamples)
        std::fprintf(stderr, "warning: shard %u: %llu non-finite eye samples were dropped\n", i,
                     static_cast<unsigned long long>(shard.nonFiniteSamples));
    return shard.complete();
}

int runRun(const BatchOptions& o) {
    gStop = &watchInterrupts(true);  // before PoCL starts threads (they inherit the blocked mask)
    BatchJob job = loadBatchJob(o.job);
    std::vector<uint32_t> todo;
    if (o.all) {
        for (uint32_t i = 0; i < job.shards; ++i) todo.push_back(i);
    } else {
        unsigned i = 0, n = 0;
        char tail = 0;
        if (std::sscanf(o.shard.c_str(), "%u/%u%c", &i, &n, &tail) != 2)
            throw InputError("batch run: --shard " + o.shard + ": expected I/N, e.g. 3/8 (shard I of N, from 0)");
        if (n != job.shards)
            throw InputError("batch run: --shard " + o.shard + ": the job " + job.path + " has " +
                             std::to_string(job.shards) + " shards, not " + std::to_string(n));
        if (i >= n) throw InputError("batch run: --shard " + o.shard + ": I must be in 0.." + std::to_string(n - 1));
        todo.push_back(i);
    }
    auto loadStart = std::chrono::steady_clock::now();
    BatchScene scene = loadBatchScene(job);
    std::unique_ptr<Device> device = openDevice(o, job);
    double loadSeconds = since(loadStart);
    for (uint32_t i : todo) {
        if (!renderOne(device.get(), scene, i, o.force, o.quiet, loadSeconds)) {
            std::fprintf(stderr, "interrupted: shard %u written with the passes done%s\n", i,
                         o.all && i + 1 < job.shards ? "; the shards after it were not started" : "");
            return kExitInterrupted;
        }
        if (gStop->load() && i != todo.back()) {
            std::fprintf(stderr, "interrupted after shard %u; the shards after it were not started\n", i);
            return kExitInterrupted;
        }
    }
    // Temporaries of killed runs are never read; they are not deleted here, as another machine's
    // run may be writing one right now (shared folders), but the user is told.
    size_t stale = 0;
    std::error_code ec;
    for (fs::directory_iterator it(shardFolder(job), ec), end; !ec && it != end; it.increment(ec))
        stale += it->path().filename().string().rfind(".shard-", 0) == 0;
    if (stale && !o.quiet)
        std::fprintf(stderr,
                     "note: %zu hidden temporary file(s) .shard-*.tmp-* in %s, left by killed runs, are never read; "
                     "delete them when no batch run is writing there\n",
                     stale, shardFolder(job).c_str());
    return kExitOk;
}

int runMerge(const BatchOptions& o) {
    auto start = std::chrono::steady_clock::now();
    std::vector<std::string> files;
    std::string jobPath, scene, output = o.output;
    MergeExpectation expect;
    bool fromJob = o.inputs.size() == 1 && fs::path(o.inputs[0]).extension() == ".json";
    if (fromJob) {
        BatchJob job = loadBatchJob(o.inputs[0]);
        BatchScene bs = loadBatchScene(job);
        jobPath = job.path;
        scene = job.scene;
        if (output.empty()) output = job.output;
        expect.sceneHash = bs.sceneHash;
        expect.settingsHash = bs.settingsHash;
        expect.settings = bs.settingsText;
        expect.passes = job.passes;
        expect.width = job.width;
        expect.height = job.height;
        std::string missing;
        for (uint32_t i = 0; i < job.shards; ++i) {
            std::string p = shardPath(job, i);
            if (fs::exists(p)) files.push_back(p);
            else if (!o.allowPartial)
                missing += "\n  shard " + std::to_string(i) + " of " + std::to_string(job.shards) + ": " + p +
                           " is missing: `photoncl batch run " + job.path + " --shard " + std::to_string(i) + "/" +
                           std::to_string(job.shards) + "` (or --all) renders it";
        }
        if (!missing.empty()) throw InputError("batch merge refused:" + missing);
    } else {
        for (const std::string& f : o.inputs)
            if (fs::path(f).extension() == ".json")
                throw InputError("batch merge: give one job file, or shard files (.pcls) and -o OUT.exr, not both");
        files = o.inputs;
        if (output.empty())
            throw InputError("batch merge: merging shard files needs -o OUT.exr (a job file names its output)");
    }
    MergeOptions mo;
    mo.allowPartial = o.allowPartial;
    MergedShards m = mergeShardFiles(files, expect, mo);
    if (!fromJob) {
        jobPath = m.shards.front().job;
        scene = "(from the shards' job " + jobPath + ")";
    }
    auto outDir = fs::path(output).parent_path();
    if (!outDir.empty() && !fs::is_directory(outDir)) throw InputError(output + ": output folder does not exist");

    Image image = m.film.resolve();
    const ShardData& s0 = m.shards.front();
    ImageMetadata meta;
    meta.scene = scene;
    meta.method = s0.method;
    std::string devices;
    for (const std::string& d : m.devices) devices += (devices.empty() ? "" : " + ") + d;
    meta.device = devices;
    uint64_t global = 0, caustic = 0, samples = 0;
    double seconds = 0;
    for (const ShardData& s : m.shards) {
        global += s.globalEmitted;
        caustic += s.causticEmitted;
        samples += s.samples;
        if (s.accounting.contains("seconds")) seconds += s.accounting["seconds"].value("total", 0.0);
    }
    meta.samples = int64_t(samples / (uint64_t(s0.width) * s0.height));
    meta.seed = s0.seed;
    meta.seconds = seconds;
    auto add = [&](const std::string& k, const std::string& v) { meta.extra.emplace_back(k, v); };
    add("settings", s0.settings);
    add("passes", std::to_string(m.passesDone));
    add("shards", std::to_string(m.shards.size()));
    add("globalPhotonsEmitted", std::to_string(global));
    add("causticPhotonsEmitted", std::to_string(caustic));
    add("sceneHash", hex64(s0.sceneHash));
    add("settingsHash", hex64(s0.settingsHash));
    add("job", jobPath);
    if (m.partial) add("partial", std::to_string(m.passesDone) + " of " + std::to_string(m.passes) + " passes");
    std::string written = writeLinearImage(output, image, meta);
    std::string png;
    if (!o.noPng) {
        png = fs::path(written).replace_extension(".png").string();
        if (!writeSrgbPng(png, image)) png.clear();
    }
    const double mergeSeconds = since(start);
    const std::string manifest = fs::path(output).replace_extension(".manifest.json").string();
    writeFileAtomically(manifest, mergeManifest(m, jobPath, scene, written, mergeSeconds).dump(2) + "\n");
    std::fprintf(stderr, "merged %zu shard(s), %u of %u passes%s, on %s: wrote %s%s%s and %s\n", m.shards.size(),
                 m.passesDone, m.passes, m.partial ? " (PARTIAL)" : "", devices.c_str(), written.c_str(),
                 png.empty() ? "" : ", ", png.c_str(), manifest.c_str());
    if (m.devices.size() > 1)
        std::fprintf(stderr,
                     "note: shards from %zu devices: the image is a correct estimate but not bit-identical to a "
                     "one-device run\n",
                     m.devices.size());
    return kExitOk;
}

}  // namespace

Run addBatchCommand(CLI::App& app) {
    auto o = std::make_shared<BatchOptions>();
    CLI::App* batch = app.add_subcommand(
        "batch",
        "Portable batch renders: a job file (JSON; README, \"Batch renders\") split into shards of passes that any "
        "machine renders independently (batch run --shard I/N), merged into exactly the image one run of all the "
        "passes gives on one device (batch merge).");
    batch->require_subcommand(1);

    CLI::App* plan = batch->add_subcommand(
        "plan", "Print the shards (pass ranges) and the device memory, host memory and time each is expected to take; "
                "time is calibrated by rendering one pass of the job at a smaller size on --device (twice, warm)");
    plan->add_option("JOB", o->job, "Job file (.json)")->required();
    plan->add_option("--device", o->device, "OpenCL device to plan and calibrate for (default: the job's, else cpu)");
    plan->add_flag("--no-calibrate", o->noCalibrate, "Memory only: render nothing");
    plan->add_flag("-q,--quiet", o->quiet, "No progress output");

    CLI::App* run = batch->add_subcommand(
        "run", "Render shard I of N (--shard I/N: passes [I·P/N, (I+1)·P/N)) or every shard still to do (--all) into "
               "<output>.shards/. A complete valid shard is skipped; an incomplete one (interrupted) is completed; a "
               "damaged or mismatched one is rendered again. Ctrl-C (or SIGTERM) finishes the current pass, writes "
               "the passes done as an incomplete shard and exits with 130; a second Ctrl-C quits at once.");
    run->add_option("JOB", o->job, "Job file (.json)")->required();
    auto shard = run->add_option("--shard", o->shard, "I/N: shard I (from 0) of the job's N");
    auto all =
        run->add_flag("--all", o->all, "Every shard that is missing, damaged, mismatched or incomplete, in order");
    shard->excludes(all);
    all->excludes(shard);
    run->add_option("--device", o->device,
                    "OpenCL device: cpu (PoCL), gpu, auto, <index> or <name substring> (default: the job's \"device\", "
                    "else cpu)");
    run->add_flag("--force", o->force, "Render the shard(s) again even if a complete valid file exists");
    run->add_flag("-q,--quiet", o->quiet, "No progress output");

    CLI::App* merge = batch->add_subcommand(
        "merge", "Check every shard (checksum, scene and settings hashes, version, pass ranges) and write the image "
                 "(EXR + PNG) and <output>.manifest.json; mismatched, duplicated, overlapping, missing, incomplete or "
                 "damaged shards are refused, each named with the reason. Same device: bit-identical to one run.");
    merge->add_option("INPUT", o->inputs, "The job file, or shard files (.pcls) with -o")->required();
    merge->add_option("-o,--output", o->output, "Output EXR (default: the job's output)");
    merge->add_flag("--allow-partial", o->allowPartial,
                    "Merge incomplete and missing shards too: the image of the passes done (the manifest says which)");
    merge->add_flag("--no-png", o->noPng, "Write only the EXR");

    Run slurm = addBatchSlurmCommand(*batch);
    CLI::App* slurmApp = batch->get_subcommands({}).back();
    return [o, plan, run, merge, slurm, slurmApp]() -> int {
        if (plan->parsed()) return runPlan(*o);
        if (run->parsed()) {
            if (!o->all && o->shard.empty()) throw InputError("batch run: give --shard I/N or --all");
            return runRun(*o);
        }
        if (merge->parsed()) return runMerge(*o);
        if (slurmApp->parsed()) return slurm();
        throw InputError("batch: expected plan, run, merge or slurm");
    };
}

}  // namespace pcl::cli
