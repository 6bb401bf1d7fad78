#include "batch/shard_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/hash.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace pcl {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "shard files are little-endian; add byte swaps here");

constexpr char kMagic[8] = {'P', 'C', 'L', 'S', 'H', 'A', 'R', 'D'};
// Version 2: 128-bit sums (version 1 held 64-bit ones, range ±2^31; refused, not converted:
// render such a shard again).
constexpr uint32_t kFormatVersion = 2;
using Fixed = FixedPointFilm::Fixed;
// Each value is 16 bytes: its low 64 bits then its high 64 bits, each little-endian, two's
// complement: on a little-endian machine that is __int128's memory, written and read as is.
constexpr size_t kValueBytes = 16;
static_assert(sizeof(Fixed) == kValueBytes, "__int128 is 16 bytes");
constexpr size_t kPixelBytes = 4 * kValueBytes;  // 3 sums and 1 weight
constexpr size_t kPrefixBytes = 8 + 4 + 4 + 8 + 8;

[[noreturn]] void fail(const std::string& path, const std::string& reason) { throw InputError(path + ": " + reason); }

// Test hook (PHOTONCL_BATCH_TEST_PAUSE): stop here long enough to be killed.
void pauseIfAsked(const char* where, const std::string& tmp) {
    const char* v = std::getenv("PHOTONCL_BATCH_TEST_PAUSE");
    if (!v || std::strcmp(v, where) != 0) return;
    std::fprintf(stderr, "[batch-test] paused %s: %s\n", where, tmp.c_str());
    std::fflush(stderr);
    std::this_thread::sleep_for(std::chrono::seconds(60));
}

// Writes all of `bytes` to fd, hashing them; false on an error (errno set).
bool writeAll(int fd, const void* data, size_t bytes, Fnv1a& hash) {
    hash.add(data, bytes);
    const char* p = static_cast<const char*>(data);
    while (bytes) {
        ssize_t n = ::write(fd, p, bytes);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        p += n;
        bytes -= size_t(n);
    }
    return true;
}

void fsyncFolder(const fs::path& folder) {
    int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
}

template <class T>
T field(const json& h, const char* key, const std::string& path) {
    auto it = h.find(key);
    if (it == h.end())
        fail(path, std::string("header has no \"") + key + "\" (not a photoncl shard, or another version)");
    try {
        return it->get<T>();
    } catch (const json::exception&) {
        fail(path, std::string("header field \"") + key + "\" has the wrong type: " + it->dump());
    }
}

uint64_t hexField(const json& h, const char* key, const std::string& path) {
    uint64_t v = 0;
    if (!parseHex64(field<std::string>(h, key, path), v))
        fail(path, std::string("header field \"") + key + "\" is not a hex hash");
    return v;
}

}  // namespace

json shardHeaderJson(const ShardData& s) {
    json h;
    h["job"] = s.job;
    h["shard"] = s.index;
    h["shards"] = s.shards;
    h["passes"] = s.passes;
    h["passFirst"] = s.range.first;
    h["passEnd"] = s.range.end;
    h["passesDone"] = s.passesDone;
    h["complete"] = s.complete();
    h["method"] = s.method;
    h["width"] = s.width;
    h["height"] = s.height;
    h["seed"] = s.seed;
    h["sceneHash"] = hex64(s.sceneHash);
    h["settingsHash"] = hex64(s.settingsHash);
    h["settings"] = s.settings;
    h["version"] = s.version;
    h["device"] = s.device;
    h["platform"] = s.platform;
    h["host"] = s.host;
    h["fixedPointFractionBits"] = FixedPointFilm::kFractionBits;
    h["fixedPointBits"] = int(8 * sizeof(FixedPointFilm::Fixed));  // (informative: the format version decides)
    h["globalPhotonsEmitted"] = s.globalEmitted;
    h["causticPhotonsEmitted"] = s.causticEmitted;
    h["globalPhotonsStored"] = s.globalStored;
    h["causticPhotonsStored"] = s.causticStored;
    h["samples"] = s.samples;
    h["nonFiniteSamples"] = s.nonFiniteSamples;
    h["accounting"] = s.accounting;
    return h;
}

void writeShardFile(const std::string& path, const ShardData& s) {
    const FixedPointFilm& film = s.film;
    if (film.width() != s.width || film.height() != s.height)
        throw InputError(path + ": shard film is " + std::to_string(film.width()) + "x" +
                         std::to_string(film.height()) + ", header says " + std::to_string(s.width) + "x" +
                         std::to_string(s.height));
    const std::string header = shardHeaderJson(s).dump(1);
    const uint64_t headerBytes = header.size();
    const uint64_t payloadBytes = (film.sums().size() + film.weights().size()) * kValueBytes;

    const std::string tmp = temporaryPathFor(path);
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) throw InputError(path + ": cannot write: cannot create " + tmp + ": " + std::strerror(errno));
    auto failWrite = [&](const std::string& what) {
        std::string reason = std::strerror(errno);
        ::close(fd);
        ::unlink(tmp.c_str());
        throw InputError(path + ": cannot write " + tmp + ": " + what + ": " + reason);
    };
    Fnv1a hash;
    const uint32_t version = kFormatVersion, reserved = 0;
    bool ok = writeAll(fd, kMagic, 8, hash) && writeAll(fd, &version, 4, hash) && writeAll(fd, &reserved, 4, hash) &&
              writeAll(fd, &headerBytes, 8, hash) && writeAll(fd, &payloadBytes, 8, hash) &&
              writeAll(fd, header.data(), header.size(), hash);
    if (!ok) failWrite("header");
    const size_t sumBytes = film.sums().size() * kValueBytes;
    // The sums in two halves, so the mid-write pause lies inside the payload.
    ok = writeAll(fd, film.sums().data(), sumBytes / 2, hash);
    if (!ok) failWrite("sums");
    if (::fsync(fd) != 0) failWrite("fsync");
    pauseIfAsked("mid-write", tmp);
    ok =
        writeAll(fd, reinterpret_cast<const char*>(film.sums().data()) + sumBytes / 2, sumBytes - sumBytes / 2, hash) &&
        writeAll(fd, film.weights().data(), film.weights().size() * kValueBytes, hash);
    if (!ok) failWrite("sums");
    const uint64_t checksum = hash.h;
    Fnv1a ignored;
    if (!writeAll(fd, &checksum, 8, ignored)) failWrite("checksum");
    if (::fsync(fd) != 0) failWrite("fsync");
    if (::close(fd) != 0) {
        ::unlink(tmp.c_str());
        throw InputError(path + ": cannot write " + tmp + ": close: " + std::strerror(errno));
    }
    pauseIfAsked("before-rename", tmp);
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw InputError(path + ": cannot rename " + tmp + " onto it: " + reason);
    }
    fsyncFolder(fs::path(path).parent_path());
}

ShardData readShardFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(path, "cannot be read (missing?)");
    const uint64_t size = static_cast<uint64_t>(in.tellg());
    in.seekg(0);
    if (size < kPrefixBytes + 8) fail(path, "truncated: " + std::to_string(size) + " bytes, not even a shard header");
    char prefix[kPrefixBytes];
    in.read(prefix, kPrefixBytes);
    if (std::memcmp(prefix, kMagic, 8) != 0) fail(path, "not a photoncl shard file (no PCLSHARD magic)");
    uint32_t version;
    uint64_t headerBytes, payloadBytes;
    std::memcpy(&version, prefix + 8, 4);
    std::memcpy(&headerBytes, prefix + 16, 8);
    std::memcpy(&payloadBytes, prefix + 24, 8);
    if (version != kFormatVersion)
        fail(path, "shard format version " + std::to_string(version) + ", expected version " +
                       std::to_string(kFormatVersion) +
                       (version == 1 ? " (version 1 held 64-bit sums; this photoncl sums in 128 bits)" : "") +
                       ": render this shard again with this photoncl");
    if (headerBytes > size || payloadBytes > size || kPrefixBytes + headerBytes + payloadBytes + 8 != size)
        fail(path, "truncated or padded: " + std::to_string(size) + " bytes, the header announces " +
                       std::to_string(kPrefixBytes + headerBytes + payloadBytes + 8));
    std::string header(headerBytes, '\0');
    in.read(header.data(), std::streamsize(headerBytes));
    if (payloadBytes % kPixelBytes)
        fail(path, "payload of " + std::to_string(payloadBytes) + " bytes is not whole pixels (" +
                       std::to_string(kPixelBytes) + " bytes each: 3 sums and a weight, 128-bit)");
    // Read straight into the film's two arrays (no second copy of the payload: a 4K shard's is
    // 531 MB): the sums of every pixel, then the weights.
    const size_t payloadPixels = payloadBytes / kPixelBytes;
    std::vector<Fixed> sums(3 * payloadPixels), weights(payloadPixels);
    in.read(reinterpret_cast<char*>(sums.data()), std::streamsize(sums.size() * kValueBytes));
    in.read(reinterpret_cast<char*>(weights.data()), std::streamsize(weights.size() * kValueBytes));
    uint64_t stored = 0;
    in.read(reinterpret_cast<char*>(&stored), 8);
    if (!in) fail(path, "cannot be read to the end");
    Fnv1a hash;
    hash.add(prefix, kPrefixBytes);
    hash.add(header);
    hash.add(sums.data(), sums.size() * kValueBytes);
    hash.add(weights.data(), weights.size() * kValueBytes);
    if (hash.h != stored)
        fail(path, "checksum mismatch (stored " + hex64(stored) + ", computed " + hex64(hash.h) +
                       "): the file is damaged; render this shard again");

    json h;
    try {
        h = json::parse(header);
    } catch (const json::exception& e) {
        fail(path, std::string("header is not JSON: ") + e.what());
    }
    ShardData s;
    s.job = field<std::string>(h, "job", path);
    s.index = field<uint32_t>(h, "shard", path);
    s.shards = field<uint32_t>(h, "shards", path);
    s.passes = field<uint32_t>(h, "passes", path);
    s.range.first = field<uint32_t>(h, "passFirst", path);
    s.range.end = field<uint32_t>(h, "passEnd", path);
    s.passesDone = field<uint32_t>(h, "passesDone", path);
    s.method = field<std::string>(h, "method", path);
    s.width = field<int>(h, "width", path);
    s.height = field<int>(h, "height", path);
    s.seed = field<uint64_t>(h, "seed", path);
    s.sceneHash = hexField(h, "sceneHash", path);
    s.settingsHash = hexField(h, "settingsHash", path);
    s.settings = field<std::string>(h, "settings", path);
    s.version = field<std::string>(h, "version", path);
    s.device = field<std::string>(h, "device", path);
    s.platform = field<std::string>(h, "platform", path);
    s.host = field<std::string>(h, "host", path);
    s.globalEmitted = field<uint64_t>(h, "globalPhotonsEmitted", path);
    s.causticEmitted = field<uint64_t>(h, "causticPhotonsEmitted", path);
    s.globalStored = field<uint64_t>(h, "globalPhotonsStored", path);
    s.causticStored = field<uint64_t>(h, "causticPhotonsStored", path);
    s.samples = field<uint64_t>(h, "samples", path);
    s.nonFiniteSamples = field<uint64_t>(h, "nonFiniteSamples", path);
    if (h.contains("accounting")) s.accounting = h["accounting"];
    if (field<int>(h, "fixedPointFractionBits", path) != FixedPointFilm::kFractionBits)
        fail(path, "fixed point with " + h["fixedPointFractionBits"].dump() + " fraction bits, expected " +
                       std::to_string(FixedPointFilm::kFractionBits));
    if (s.range.end < s.range.first || s.range.end > s.passes || s.passesDone > s.range.count() || s.index >= s.shards)
        fail(path, "inconsistent header: shard " + std::to_string(s.index) + " of " + std::to_string(s.shards) +
                       ", passes [" + std::to_string(s.range.first) + ", " + std::to_string(s.range.end) + "), " +
                       std::to_string(s.passesDone) + " done");
    if (s.width <= 0 || s.height <= 0 || s.width > 65536 || s.height > 65536)
        fail(path, "inconsistent header: size " + std::to_string(s.width) + "x" + std::to_string(s.height));
    const size_t pixels = size_t(s.width) * s.height;
    if (payloadPixels != pixels)
        fail(path, "payload holds " + std::to_string(payloadPixels) + " pixels, a " + std::to_string(s.width) + "x" +
                       std::to_string(s.height) + " shard holds " + std::to_string(pixels));
    s.film = FixedPointFilm(s.width, s.height, std::move(sums), std::move(weights));
    return s;
}

}  // namespace pcl
