#include "batch/batch_job.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "render/photon_renderer.h"
#include "scene/json_parse.h"
#include "scene/load_scene.h"
#include "scene/scene_error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace pcl {
namespace {

// clang-format off
const char* const kKeys[] = {"scene",        "output",       "method",      "shards",        "passes",
                             "seed",         "width",        "height",      "globalPhotons", "causticPhotons",
                             "strata",       "gatherRays",   "k",           "causticK",      "lightSamples",
                             "gatherImportance", "radius",   "alpha",       "maxRadius",     "filter",
                             "gatherSource", "visibility",   "device",      "maxBufferMib",  "structure", "threads",
                             "caustics",     "emitterStrata"};
// clang-format on

std::string allowedKeys() {
    std::string out;
    for (const char* k : kKeys) out += std::string(out.empty() ? "" : ", ") + k;
    return out;
}

// Reads one field with the loader's message shape: "FILE: KEY: expected X, got Y".
struct Reader {
    const std::string& file;
    const json& root;

    const json* find(const char* key) const {
        auto it = root.find(key);
        return it == root.end() ? nullptr : &*it;
    }
    uint64_t integer(const char* key, uint64_t lo, uint64_t hi, uint64_t fallback) const {
        const json* v = find(key);
        if (!v) return fallback;
        const std::string expected = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        // Unsigned integers exactly (seeds use all 64 bits); a whole float (4.0) is accepted.
        const bool whole = v->is_number_unsigned() ||
                           (v->is_number_float() && std::isfinite(v->get<double>()) &&
                            std::floor(v->get<double>()) == v->get<double>() && v->get<double>() >= 0);
        if (!whole) failInput(file, key, expected, showJson(*v));
        const double d = v->get<double>();
        if (d < double(lo) || d > double(hi)) failInput(file, key, expected, showJson(*v));
        return v->is_number_unsigned() ? v->get<uint64_t>() : uint64_t(d);
    }
    float real(const char* key, double lo, double hi, float fallback, const char* expected) const {
        const json* v = find(key);
        if (!v) return fallback;
        if (!v->is_number() || !std::isfinite(v->get<double>()) || v->get<double>() < lo || v->get<double>() > hi)
            failInput(file, key, expected, showJson(*v));
        return v->get<float>();
    }
    std::string text(const char* key, const std::string& fallback,
                     std::initializer_list<const char*> allowed = {}) const {
        const json* v = find(key);
        if (!v) return fallback;
        std::string expected = "a string";
        if (allowed.size()) {
            expected = "one of";
            for (const char* a : allowed) expected += std::string(" \"") + a + "\"";
        }
        if (!v->is_string()) failInput(file, key, expected, showJson(*v));
        std::string s = v->get<std::string>();
        if (allowed.size() &&
            std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return s == a; }) == allowed.end())
            failInput(file, key, expected, showJson(*v));
        if (s.empty()) failInput(file, key, "a non-empty string", showJson(*v));
        return s;
    }
    bool flag(const char* key, bool fallback) const {
        const json* v = find(key);
        if (!v) return fallback;
        if (!v->is_boolean()) failInput(file, key, "true or false", showJson(*v));
        return v->get<bool>();
    }
};

std::string resolveAgainst(const fs::path& folder, const std::string& p) {
    fs::path path(p);
    return (path.is_absolute() ? path : folder / path).lexically_normal().string();
}

}  // namespace

BatchJob loadBatchJob(const std::string& path) {
    const json root = parseSceneJson(readTextFile(path), path);
    if (!root.is_object()) failInput(path, "(top level)", "an object", showJson(root));
    for (auto it = root.begin(); it != root.end(); ++it)
        if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return it.key() == k; }) ==
            std::end(kKeys))
            failInput(path, it.key(), "one of the keys " + allowedKeys(), "unknown key \"" + it.key() + "\"");
    for (const char* key : {"scene", "output", "shards"})
        if (!root.contains(key)) failInput(path, key, "a value (the key is required)", "nothing (the key is missing)");

    Reader r{path, root};
    const fs::path folder = fs::path(path).parent_path();
    BatchJob job;
    job.path = path;
    job.scene = resolveAgainst(folder, r.text("scene", ""));
    job.output = resolveAgainst(folder, r.text("output", ""));
    // path: the CPU reference path tracer, one sample per pixel per pass (its samples are
    // indexed by sample number: PathTracerSettings::firstSample), on the host, not a device.
    job.method = r.text("method", "fg", {"fg", "direct", "progressive", "path"});
    job.shards = static_cast<uint32_t>(r.integer("shards", 1, 100000, 1));
    job.seed = r.integer("seed", 0, UINT64_MAX, 0);
    job.width = static_cast<int>(r.integer("width", 1, 65536, 0));
    job.height = static_cast<int>(r.integer("height", 1, 65536, 0));
    job.globalPhotons = static_cast<uint32_t>(r.integer("globalPhotons", 1, 2000000000u, 0));
    job.causticPhotons = static_cast<uint32_t>(r.integer("causticPhotons", 1, 2000000000u, 0));
    job.strata = static_cast<uint32_t>(r.integer("strata", 1, 16, 0));
    job.gatherRays = static_cast<uint32_t>(r.integer("gatherRays", 1, 4096, 0));
    job.k = static_cast<uint32_t>(r.integer("k", 1, 500, 0));
    job.causticK = static_cast<uint32_t>(r.integer("causticK", 1, 500, 0));
    job.lightSamples = static_cast<uint32_t>(r.integer("lightSamples", 1, 256, 0));
    job.gatherImportance = static_cast<uint32_t>(r.integer("gatherImportance", 0, 16, 0));
    job.radius = r.real("radius", 1e-30, 1e30, 0.0f, "a positive number (progressive's first radius)");
    job.alpha = r.real("alpha", 0.01, 0.99, 2.0f / 3.0f, "a number in [0.01, 0.99]");
    job.maxRadius = r.real("maxRadius", 1e-30, 1e30, 0.0f, "a positive number");
    job.filter = r.text("filter", "cone", {"box", "cone", "epanechnikov", "gaussian"});
    job.gatherSource = r.text("gatherSource", "precomputed", {"precomputed", "estimate"});
    job.structure = r.text("structure", "kd-tree", {"kd-tree", "hash-grid"});
    job.caustics = r.text("caustics", "", {"", "connect", "map"});
    job.emitterStrata = r.find("emitterStrata") ? int(r.integer("emitterStrata", 0, 16, 0)) : -1;
    job.visibility = r.flag("visibility", false);
    job.device = r.text("device", "cpu");
    job.maxBufferMib = r.integer("maxBufferMib", 1, uint64_t(1) << 30, 0);
    job.threads = static_cast<int>(r.integer("threads", 0, 4096, 0));

    // The resolution and default passes follow from the scene's camera, as in `render`.
    if (!job.width || !job.height || !root.contains("passes")) {
        Scene scene = loadScene(job.scene);
        const Camera& cam = scene.camera;
        int w = job.width, h = job.height;
        job.width = w ? w : (h ? std::max(1, h * cam.width / cam.height) : cam.width);
        job.height = h ? h : (w ? std::max(1, w * cam.height / cam.width) : cam.height);
    }
    // path: `render --method path`'s default of 64 samples per pixel.
    const uint32_t fallback =
        job.method == "path" ? 64u : defaultPasses(parseRenderMethod(job.method), job.width, job.height);
    job.passes = static_cast<uint32_t>(r.integer("passes", 1, 1u << 20, fallback));
    if (job.shards > job.passes)
        failInput(path, "shards",
                  "at most the number of passes (" + std::to_string(job.passes) + "): a shard renders whole passes",
                  std::to_string(job.shards));
    return job;
}

PassRange shardPasses(const BatchJob& job, uint32_t i) {
    PassRange r;
    r.first = static_cast<uint32_t>(uint64_t(i) * job.passes / job.shards);
    r.end = static_cast<uint32_t>(uint64_t(i + 1) * job.passes / job.shards);
    return r;
}

std::string shardFolder(const BatchJob& job) { return job.output + ".shards"; }

std::string shardPath(const BatchJob& job, uint32_t i) {
    char name[64];
    std::snprintf(name, sizeof name, "shard-%04u-of-%04u.pcls", i, job.shards);
    return (fs::path(shardFolder(job)) / name).string();
}

std::string manifestPath(const BatchJob& job) {
    return fs::path(job.output).replace_extension(".manifest.json").string();
}

}  // namespace pcl
