#include "batch/merge.h"

#include <algorithm>
#include <ctime>
#include <map>
#include <sstream>
#include <utility>

#include "core/error.h"
#include "core/hash.h"

namespace pcl {
namespace {

std::map<std::string, std::string> settingsMap(const std::string& text) {
    std::map<std::string, std::string> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ';')) {
        size_t eq = item.find('=');
        if (eq != std::string::npos) out[item.substr(0, eq)] = item.substr(eq + 1);
    }
    return out;
}

std::string range(uint32_t a, uint32_t b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + ")"; }

}  // namespace

std::string settingsDifference(const std::string& a, const std::string& b) {
    auto ma = settingsMap(a), mb = settingsMap(b);
    std::string out;
    for (const auto& [k, v] : ma) {
        auto it = mb.find(k);
        std::string w = it == mb.end() ? "(none)" : it->second;
        if (w != v) out += (out.empty() ? "" : ", ") + k + " " + v + " vs " + w;
    }
    for (const auto& [k, w] : mb)
        if (!ma.count(k)) out += (out.empty() ? "" : ", ") + k + " (none) vs " + w;
    return out.empty() ? "(same text, different hash)" : out;
}

MergedShards mergeShardFiles(const std::vector<std::string>& files, const MergeExpectation& expectIn,
                             const MergeOptions& options) {
    if (files.empty()) throw InputError("batch merge: no shard files to merge");
    std::vector<std::string> problems;
    struct Entry {
        std::string file;
        ShardData shard;
    };
    std::vector<Entry> shards;
    // Each file's sums are added as soon as it is read and checked, and its film dropped, so a
    // merge holds the sum and one shard's film (a 4K film of 128-bit sums is 531 MB). Integer
    // sums: the order of the additions cannot change the result; any problem found later still
    // refuses the merge.
    FixedPointFilm sum;
    int sumWidth = expectIn.width, sumHeight = expectIn.height;
    for (const std::string& f : files) {
        try {
            Entry e{f, readShardFile(f)};
            if (!sumWidth) sumWidth = e.shard.width, sumHeight = e.shard.height;
            if (e.shard.width == sumWidth && e.shard.height == sumHeight) {
                if (sum.width() == 0) sum = std::move(e.shard.film);  // 0 + x is x: no zero film to add to
                else sum.add(e.shard.film);
            }
            e.shard.film = FixedPointFilm();
            shards.push_back(std::move(e));
        } catch (const InputError& e) {
            problems.push_back(std::string(e.what()) + " (refused)");
        }
    }
    MergeExpectation expect = expectIn;
    std::string expectFrom = "the job";
    if (!shards.empty()) {
        const ShardData& s0 = shards.front().shard;
        if (!expect.sceneHash) expect.sceneHash = s0.sceneHash, expectFrom = shards.front().file;
        if (!expect.settingsHash) expect.settingsHash = s0.settingsHash, expect.settings = s0.settings;
        if (!expect.passes) expect.passes = s0.passes;
        if (!expect.width) expect.width = s0.width, expect.height = s0.height;
    }
    const std::string version = shards.empty() ? "" : shards.front().shard.version;
    for (const Entry& e : shards) {
        const ShardData& s = e.shard;
        if (s.sceneHash != expect.sceneHash)
            problems.push_back(e.file + ": rendered from another scene (scene hash " + hex64(s.sceneHash) + ", " +
                               expectFrom + " has " + hex64(expect.sceneHash) +
                               "): the scene file or a file it includes changed; render this shard again");
        if (s.settingsHash != expect.settingsHash)
            problems.push_back(e.file + ": rendered with other settings (" +
                               settingsDifference(expect.settings, s.settings) + ", " + expectFrom + " first)");
        else if (s.passes != expect.passes || s.width != expect.width || s.height != expect.height)
            problems.push_back(e.file + ": a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                               " shard of " + std::to_string(s.passes) + " passes, expected " +
                               std::to_string(expect.width) + "x" + std::to_string(expect.height) + " and " +
                               std::to_string(expect.passes));
        if (s.version != version)
            problems.push_back(e.file + ": rendered by photoncl " + s.version + ", " + shards.front().file + " by " +
                               version + ": versions may render different bits; render every shard with one version");
        if (!s.complete() && !options.allowPartial)
            problems.push_back(e.file + ": incomplete: " + std::to_string(s.passesDone) + " of " +
                               std::to_string(s.range.count()) + " passes " + range(s.range.first, s.range.end) +
                               " done (interrupted); `photoncl batch run JOB --all` completes it, or merge with "
                               "--allow-partial");
    }
    // Ranges: sorted by first pass they must tile [0, P) with neither gaps nor overlaps.
    std::sort(shards.begin(), shards.end(), [](const Entry& a, const Entry& b) {
        return a.shard.range.first != b.shard.range.first ? a.shard.range.first < b.shard.range.first : a.file < b.file;
    });
    bool partial = false;
    uint32_t covered = 0;
    for (size_t i = 0; i < shards.size(); ++i) {
        const ShardData& s = shards[i].shard;
        if (i > 0 && s.range.first < shards[i - 1].shard.range.end) {
            const ShardData& p = shards[i - 1].shard;
            bool same = p.range.first == s.range.first && p.range.end == s.range.end;
            problems.push_back(shards[i - 1].file + " and " + shards[i].file +
                               (same ? ": duplicates, both hold passes " : ": overlap: passes ") +
                               range(p.range.first, p.range.end) +
                               (same ? "" : " and " + range(s.range.first, s.range.end)) + "; merge each pass once");
        } else if (s.range.first > covered) {
            if (!options.allowPartial)
                problems.push_back("passes " + range(covered, s.range.first) + " are missing: no shard holds them");
            partial = true;
        }
        covered = std::max(covered, s.range.end);
    }
    if (covered < expect.passes) {
        if (!options.allowPartial)
            problems.push_back("passes " + range(covered, expect.passes) + " are missing: no shard holds them");
        partial = true;
    }
    if (!problems.empty()) {
        std::string msg = "batch merge refused (" + std::to_string(problems.size()) + " problem" +
                          (problems.size() > 1 ? "s" : "") + "):";
        for (const std::string& p : problems) msg += "\n  " + p;
        throw InputError(msg);
    }

    MergedShards out;
    out.passes = expect.passes;
    out.film = std::move(sum);
    for (Entry& e : shards) {
        out.passesDone += e.shard.passesDone;
        partial = partial || !e.shard.complete();
        if (std::find(out.devices.begin(), out.devices.end(), e.shard.device) == out.devices.end())
            out.devices.push_back(e.shard.device);
        out.files.push_back(e.file);
        out.shards.push_back(std::move(e.shard));
    }
    out.partial = partial;
    return out;
}

nlohmann::json mergeManifest(const MergedShards& m, const std::string& job, const std::string& scene,
                             const std::string& image, double mergeSeconds) {
    using nlohmann::json;
    json j;
    j["job"] = job;
    j["scene"] = scene;
    j["image"] = image;
    std::time_t t = std::time(nullptr);
    char when[32];
    std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    j["merged"] = when;
    j["mergeSeconds"] = mergeSeconds;
    if (!m.shards.empty()) {
        j["sceneHash"] = hex64(m.shards.front().sceneHash);
        j["settingsHash"] = hex64(m.shards.front().settingsHash);
        j["settings"] = m.shards.front().settings;
        j["version"] = m.shards.front().version;
    }
    j["passes"] = m.passes;
    j["passesDone"] = m.passesDone;
    j["partial"] = m.partial;
    j["devices"] = m.devices;
    j["bitIdenticalToOneRun"] = m.devices.size() == 1 && !m.partial;
    json shards = json::array(), seconds = json::object();
    uint64_t rss = 0, device = 0;
    for (size_t i = 0; i < m.shards.size(); ++i) {
        const ShardData& s = m.shards[i];
        json e = shardHeaderJson(s);
        e.erase("settings");
        e["file"] = m.files[i];
        shards.push_back(e);
        if (s.accounting.contains("seconds"))
            for (auto it = s.accounting["seconds"].begin(); it != s.accounting["seconds"].end(); ++it)
                seconds[it.key()] = seconds.value(it.key(), 0.0) + it.value().get<double>();
        rss = std::max<uint64_t>(rss, s.accounting.value("hostMaxRssBytes", uint64_t(0)));
        device = std::max<uint64_t>(device, s.accounting.value("deviceBytesUpperBound", uint64_t(0)));
    }
    j["shards"] = shards;
    j["totals"] = {
        {"secondsByStage", seconds}, {"largestHostMaxRssBytes", rss}, {"largestDeviceBytesUpperBound", device}};
    return j;
}

}  // namespace pcl
