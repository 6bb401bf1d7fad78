#include "device/program_cache.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <system_error>
#include <unistd.h>
#include <vector>

#include "core/clock.h"
#include "device/embedded_kernels.h"

namespace fs = std::filesystem;

namespace pcl {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'L', 'B', 'I', 'N', '0', '1'};
constexpr size_t kHeaderSize = 24;  // magic, binary length, FNV-1a 64 of the binary

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? std::string(v) : std::string();
}

std::string readFile(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return {};
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Lines as Python's str.splitlines() gives them for ASCII text: \n, \r\n and \r end a line,
// and a final line ending does not start an empty line.
std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::string cur;
    for (size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (c == '\n' || c == '\r') {
            lines.push_back(cur);
            cur.clear();
            if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
        } else {
            cur += c;
        }
    }
    if (!cur.empty()) lines.push_back(cur);
    return lines;
}

// The same expansion as scripts/embed_kernels.py: each include inlined once, #line markers
// before and after, so embedded and on-disk sources are byte-for-byte identical.
void expand(const fs::path& file, const fs::path& kernelDir, std::set<fs::path>& seen, std::vector<std::string>& out) {
    static const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)"\s*$)re");
    const std::string rel = file.lexically_relative(kernelDir).generic_string();
    std::ifstream probe(file, std::ios::binary);
    if (!probe) throw DeviceError(file.string() + ": cannot read kernel source");
    out.push_back("#line 1 \"" + rel + "\"");
    std::vector<std::string> lines = splitLines(readFile(file));
    for (size_t i = 0; i < lines.size(); ++i) {
        const size_t number = i + 1;
        std::smatch m;
        if (!std::regex_match(lines[i], m, include)) {
            out.push_back(lines[i]);
            continue;
        }
        fs::path target = fs::weakly_canonical(file.parent_path() / m[1].str());
        if (!fs::exists(target)) target = fs::weakly_canonical(kernelDir / m[1].str());
        if (!fs::exists(target))
            throw DeviceError(rel + ":" + std::to_string(number) + ": include not found: " + m[1].str());
        if (seen.insert(target).second) expand(target, kernelDir, seen, out);
        out.push_back("#line " + std::to_string(number + 1) + " \"" + rel + "\"");
    }
}

void putU64(std::string& s, uint64_t v) {
    for (int i = 0; i < 8; ++i) s += char((v >> (8 * i)) & 0xff);
}
uint64_t getU64(const std::string& s, size_t at) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | uint8_t(s[at + i]);
    return v;
}

// Hash a field with its length first, so ("ab","c") and ("a","bc") differ.
uint64_t hashField(uint64_t h, const std::string& s) {
    uint64_t n = s.size();
    h = fnv1a64(&n, sizeof n, h);
    return fnv1a64(s.data(), s.size(), h);
}

}  // namespace

fs::path cacheDirectory() {
    std::string dir = env("PHOTONCL_CACHE_DIR");
    if (!dir.empty()) return dir;
    // The XDG spec says a relative XDG_CACHE_HOME is invalid and must be ignored.
    std::string xdg = env("XDG_CACHE_HOME");
    if (!xdg.empty() && fs::path(xdg).is_absolute()) return fs::path(xdg) / "photoncl";
    std::string home = env("HOME");
    if (!home.empty()) return fs::path(home) / ".cache" / "photoncl";
    return {};
}

std::optional<fs::path> kernelDirOverride() {
    std::string dir = env("PHOTONCL_KERNEL_DIR");
    if (dir.empty()) return std::nullopt;
    return fs::path(dir);
}

std::string expandKernelFile(const fs::path& kernelDir, const std::string& stage) {
    const fs::path dir = fs::weakly_canonical(kernelDir);
    const fs::path file = dir / (stage + ".cl");
    if (!fs::exists(file))
        throw DeviceError("kernel " + stage + ": " + file.string() +
                          " not found (PHOTONCL_KERNEL_DIR=" + kernelDir.string() + ")");
    std::set<fs::path> seen;
    std::vector<std::string> lines;
    expand(file, dir, seen, lines);
    std::string text;
    for (size_t i = 0; i < lines.size(); ++i) {
        if (i) text += '\n';
        text += lines[i];
    }
    return text + "\n";
}

std::string kernelSource(const std::string& stage, const std::optional<fs::path>& kernelDir) {
    if (kernelDir) return expandKernelFile(*kernelDir, stage);
    for (const EmbeddedKernel* k = kEmbeddedKernels; k->name; ++k)
        if (stage == k->name) return k->source;
    std::string known;
    for (const EmbeddedKernel* k = kEmbeddedKernels; k->name; ++k) known += std::string(" ") + k->name;
    throw DeviceError("kernel " + stage + ": no kernels/" + stage + ".cl embedded (have:" + known + ")");
}

ProgramCache::ProgramCache(cl::Context context, DeviceInfo device, std::optional<fs::path> kernelDir,
                           std::optional<fs::path> cacheDir)
    : context_(std::move(context)), device_(std::move(device)), kernelDir_(std::move(kernelDir)),
      cacheDir_(std::move(cacheDir)) {
    if (cacheDir_ && cacheDir_->empty()) cacheDir_.reset();
}

std::string mapBuildLogLines(const std::string& log, const std::string& source) {
    // origin[n - 1]: the file and line of the expanded source's line n.
    static const std::regex marker(R"re(^\s*#\s*line\s+(\d+)\s+"([^"]*)"\s*$)re");
    std::vector<std::pair<std::string, long>> origin;
    std::string file = "<kernel>";
    long next = 1;
    std::istringstream in(source);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        origin.emplace_back(file, next);
        if (std::regex_match(line, m, marker)) {
            file = m[2];
            next = std::stol(m[1]);
        } else {
            ++next;
        }
    }
    static const std::regex anonymous(R"re(<(kernel|source|input)>:(\d+):)re");
    std::string out;
    auto rest = log.cbegin();
    for (std::sregex_iterator it(log.begin(), log.end(), anonymous), end; it != end; ++it) {
        const std::smatch& m = *it;
        out.append(rest, m[0].first);
        const long n = std::stol(m[2]);
        if (n >= 1 && size_t(n) <= origin.size())
            out += origin[n - 1].first + ":" + std::to_string(origin[n - 1].second) + ":";
        else out += m.str();
        rest = m[0].second;
    }
    out.append(rest, log.cend());
    return out;
}

std::string ProgramCache::fullOptions(const std::string& options) const {
    std::string o = kDefaultBuildOptions;
    // OpenCL lets single-precision division and sqrt be off by 2.5 and 3 ulp unless asked (GPUs
    // take that leave; PoCL does not): the twins' are IEEE, and an estimate filter's 1 - d²/r² at
    // the k-th photon must come out 0 on both sides, not 6e-8 on one.
    if (device_.correctlyRoundedDivideSqrt) o += " -cl-fp32-correctly-rounded-divide-sqrt";
    if (!options.empty()) o += " " + options;
    if (const char* extra = std::getenv("PHOTONCL_CL_OPTIONS"); extra && *extra)  // tuning and GPU experiments
        o += std::string(" ") + extra;
    return o;
}

fs::path ProgramCache::entryPathFor(const std::string& stage, const std::string& source,
                                    const std::string& options) const {
    if (!cacheDir_) return {};
    uint64_t h = fnv1a64(kMagic, sizeof kMagic);
    h = hashField(h, source);
    h = hashField(h, options);
    h = hashField(h, device_.platformVersion);
    h = hashField(h, device_.name);
    h = hashField(h, device_.driver);
    return *cacheDir_ / (stage + "-" + hex64(h) + ".bin");
}

fs::path ProgramCache::entryPath(const std::string& stage, const std::string& options) const {
    return entryPathFor(stage, kernelSource(stage, kernelDir_), fullOptions(options));
}

std::optional<cl::Program> ProgramCache::loadBinary(const fs::path& file, const std::string& options) {
    std::error_code ec;
    if (!fs::exists(file, ec)) return std::nullopt;
    const std::string data = readFile(file);
    const bool intact = data.size() >= kHeaderSize && std::memcmp(data.data(), kMagic, sizeof kMagic) == 0 &&
                        getU64(data, 8) == data.size() - kHeaderSize &&
                        getU64(data, 16) == fnv1a64(data.data() + kHeaderSize, data.size() - kHeaderSize);
    if (intact) {
        try {
            cl::Program::Binaries binaries{std::vector<unsigned char>(data.begin() + kHeaderSize, data.end())};
            std::vector<cl_int> status;
            cl::Program program(context_, {device_.clDevice}, binaries, &status);
            program.build({device_.clDevice}, options.c_str());
            fs::last_write_time(file, fs::file_time_type::clock::now(), ec);  // recently used
            return program;
        } catch (const cl::Error&) {
            // The device refused it (a driver update the key missed, say): rebuild from source.
        }
    }
    ++stats_.rejected;
    fs::remove(file, ec);
    return std::nullopt;
}

void ProgramCache::storeBinary(const fs::path& file, const cl::Program& program) {
    // The cache is an optimisation: any failure here leaves the program usable and no file.
    static std::atomic<unsigned> counter{0};
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    std::vector<std::vector<unsigned char>> binaries;
    try {
        binaries = program.getInfo<CL_PROGRAM_BINARIES>();
    } catch (const cl::Error&) {
        return;
    }
    if (binaries.size() != 1 || binaries[0].empty()) return;
    const std::vector<unsigned char>& bin = binaries[0];
    std::string header(kMagic, sizeof kMagic);
    putU64(header, bin.size());
    putU64(header, fnv1a64(bin.data(), bin.size()));
    const fs::path tmp = file.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(header.data(), header.size());
        out.write(reinterpret_cast<const char*>(bin.data()), bin.size());
        if (!out.flush()) {
            out.close();
            fs::remove(tmp, ec);
            return;
        }
    }
    fs::rename(tmp, file, ec);
    if (ec) fs::remove(tmp, ec);
}

void ProgramCache::prune(const std::string& stage, const fs::path& keep) {
    // Entries are "<stage>-<16 hex>.bin": match the exact length so "trace" leaves
    // "trace_photons-…" alone.
    const std::string prefix = stage + "-";
    const size_t nameLength = prefix.size() + 16 + 4;
    std::vector<std::pair<fs::file_time_type, fs::path>> entries;
    std::error_code ec;
    for (fs::directory_iterator it(*cacheDir_, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() != nameLength || name.compare(0, prefix.size(), prefix) != 0 ||
            name.compare(name.size() - 4, 4, ".bin") != 0 || it->path() == keep)
            continue;
        std::error_code timeError;
        auto time = fs::last_write_time(it->path(), timeError);
        if (!timeError) entries.emplace_back(time, it->path());
    }
    if (entries.size() + 1 <= maxEntriesPerStage_) return;
    std::sort(entries.begin(), entries.end());  // oldest first
    const size_t excess = entries.size() + 1 - maxEntriesPerStage_;
    for (size_t i = 0; i < excess && i < entries.size(); ++i) fs::remove(entries[i].second, ec);
}

cl::Program ProgramCache::build(const std::string& stage, const std::string& options) {
    const auto start = std::chrono::steady_clock::now();
    auto finish = [&] { stats_.lastSeconds = since(start); };
    const std::string source = kernelSource(stage, kernelDir_);
    const std::string opts = fullOptions(options);
    const fs::path entry = entryPathFor(stage, source, opts);
    if (!entry.empty()) {
        if (std::optional<cl::Program> cached = loadBinary(entry, opts)) {
            ++stats_.loaded;
            finish();
            return *cached;
        }
    }

    const std::string where = kernelDir_ ? (*kernelDir_ / (stage + ".cl")).string()
                                         : "kernels/" + stage + ".cl (embedded)";
    cl::Program program;
    try {
        program = cl::Program(context_, source);
        program.build({device_.clDevice}, opts.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_.clDevice);
        } catch (const cl::Error&) {
        }
        while (!log.empty() && (log.back() == '\n' || log.back() == '\0')) log.pop_back();
        std::ostringstream msg;
        msg << where << ": build failed on " << device_.name << " (" << device_.platform << ", driver "
            << device_.driver << ") with options '" << opts << "': " << clErrorName(e.err()) << " (" << e.err() << ")";
        if (!log.empty()) msg << "\n" << mapBuildLogLines(log, source);
        throw DeviceError(msg.str());
    }
    ++stats_.compiled;
    if (!entry.empty()) {
        storeBinary(entry, program);
        prune(stage, entry);
    }
    finish();
    return program;
}

}  // namespace pcl
