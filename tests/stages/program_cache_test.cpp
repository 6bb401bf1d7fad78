// The binary cache: a miss builds from source and stores a binary, a hit loads it, a damaged
// entry is rebuilt rather than trusted; build errors name the file, the device and the log;
// PHOTONCL_KERNEL_DIR reads sources from disk.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "device/probe.h"
#include "device/program_cache.h"
#include "device_fixture.h"

namespace fs = std::filesystem;

namespace {

using pcl::ProgramCache;
using pcl::test::TempDir;
using pcl::test::testDevice;

ProgramCache cacheIn(const fs::path& dir, std::optional<fs::path> kernelDir = std::nullopt) {
    return ProgramCache(testDevice().context(), testDevice().info(), kernelDir, dir);
}

// A program loaded from the cache must still run: probe_sizes through it.
void expectProbeRuns(cl::Program program) {
    pcl::Device& dev = testDevice();
    cl::KernelFunctor<cl::Buffer> k(program, "probe_sizes");
    const size_t n = pcl::sharedStructs().size();
    cl::Buffer out = dev.allocate<uint32_t>(n);
    dev.launch("probe", k, cl::NDRange(1), out);
    std::vector<uint32_t> sizes = dev.download<uint32_t>(out, n);
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(sizes[i], pcl::sharedStructs()[i].hostSize);
}

void writeFile(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

TEST(ProgramCache, MissThenHit) {
    TempDir dir;
    ProgramCache cold = cacheIn(dir.path());
    const fs::path entry = cold.entryPath("probe");
    EXPECT_EQ(entry.parent_path(), dir.path());
    EXPECT_FALSE(fs::exists(entry));
    expectProbeRuns(cold.build("probe"));
    EXPECT_EQ(cold.stats().compiled, 1);
    EXPECT_EQ(cold.stats().loaded, 0);
    ASSERT_TRUE(fs::exists(entry));
    const double coldSeconds = cold.stats().lastSeconds;

    ProgramCache warm = cacheIn(dir.path());
    expectProbeRuns(warm.build("probe"));
    EXPECT_EQ(warm.stats().compiled, 0);
    EXPECT_EQ(warm.stats().loaded, 1);
    EXPECT_EQ(warm.stats().rejected, 0);
    std::printf("  probe program: %.3f s from source, %.3f s from the cache on %s\n", coldSeconds,
                warm.stats().lastSeconds, testDevice().info().name.c_str());
    // No temporary files left beside the entry.
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) files += e.is_regular_file();
    EXPECT_EQ(files, 1);
}

TEST(ProgramCache, OptionsAndSourceAreInTheKey) {
    TempDir dir;
    ProgramCache cache = cacheIn(dir.path());
    EXPECT_NE(cache.entryPath("probe"), cache.entryPath("probe", "-DPCL_SOMETHING=1"));
    EXPECT_NE(cache.entryPath("probe"), cache.entryPath("probe", "-DPCL_SOMETHING=2"));
    TempDir kernels;
    writeFile(kernels.path() / "probe.cl", "__kernel void probe_sizes(__global uint* s) { s[0] = 1; }\n");
    EXPECT_NE(cache.entryPath("probe"), cacheIn(dir.path(), kernels.path()).entryPath("probe"));
}

// Truncated and bit-flipped entries fail the header's length or checksum: deleted, rebuilt.
TEST(ProgramCache, DamagedEntryIsRebuiltNotTrusted) {
    TempDir dir;
    ProgramCache first = cacheIn(dir.path());
    first.build("probe");
    const fs::path entry = first.entryPath("probe");
    const auto size = fs::file_size(entry);
    ASSERT_GT(size, 24u);

    fs::resize_file(entry, size / 2);
    ProgramCache second = cacheIn(dir.path());
    expectProbeRuns(second.build("probe"));
    EXPECT_EQ(second.stats().rejected, 1);
    EXPECT_EQ(second.stats().compiled, 1);
    EXPECT_EQ(second.stats().loaded, 0);
    EXPECT_EQ(fs::file_size(entry), size);  // rewritten whole

    {
        std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(size - 10));
        char c = 0;
        f.get(c);
        f.seekp(std::streamoff(size - 10));
        f.put(char(c ^ 0x5a));
    }
    ProgramCache third = cacheIn(dir.path());
    expectProbeRuns(third.build("probe"));
    EXPECT_EQ(third.stats().rejected, 1);
    EXPECT_EQ(third.stats().compiled, 1);

    writeFile(entry, "PCLBIN01 but nothing else");
    ProgramCache fourth = cacheIn(dir.path());
    expectProbeRuns(fourth.build("probe"));
    EXPECT_EQ(fourth.stats().rejected, 1);

    ProgramCache fifth = cacheIn(dir.path());
    fifth.build("probe");
    EXPECT_EQ(fifth.stats().loaded, 1);
}

// Each stage keeps its most recently used entries; a hit counts as a use; other stages' files
// are left alone.
TEST(ProgramCache, KeepsOnlyRecentEntriesPerStage) {
    TempDir dir;
    writeFile(dir.path() / "probe_other-0123456789abcdef.bin", "another stage");
    ProgramCache cache = cacheIn(dir.path());
    cache.setMaxEntriesPerStage(2);
    const fs::path v1 = cache.entryPath("probe", "-DPCL_V=1"), v2 = cache.entryPath("probe", "-DPCL_V=2"),
                   v3 = cache.entryPath("probe", "-DPCL_V=3");
    cache.build("probe", "-DPCL_V=1");
    cache.build("probe", "-DPCL_V=2");
    ProgramCache again = cacheIn(dir.path());
    again.setMaxEntriesPerStage(2);
    again.build("probe", "-DPCL_V=1");  // a hit: v1 is now the most recently used
    EXPECT_EQ(again.stats().loaded, 1);
    again.build("probe", "-DPCL_V=3");
    EXPECT_TRUE(fs::exists(v1));
    EXPECT_FALSE(fs::exists(v2));
    EXPECT_TRUE(fs::exists(v3));
    EXPECT_TRUE(fs::exists(dir.path() / "probe_other-0123456789abcdef.bin"));
}

// A cache directory that cannot be written is no error: the program is built and not stored.
TEST(ProgramCache, UnwritableCacheDirStillBuilds) {
    TempDir dir;
    writeFile(dir.path() / "file", "x");
    ProgramCache cache = cacheIn(dir.path() / "file" / "sub");
    expectProbeRuns(cache.build("probe"));
    EXPECT_EQ(cache.stats().compiled, 1);
}

TEST(ProgramCache, SyntaxErrorNamesFileDeviceAndLog) {
    TempDir kernels, cache;
    fs::create_directories(kernels.path() / "shared");
    writeFile(kernels.path() / "shared" / "helper.h", "#define PCL_HELPER 1\n");
    writeFile(kernels.path() / "broken.cl", "#include \"shared/helper.h\"\n"
                                            "__kernel void broken_run(__global int* x) {\n"
                                            "    x[0] = pcl_undeclared_thing;\n"
                                            "}\n");
    ProgramCache programs = cacheIn(cache.path(), kernels.path());
    try {
        programs.build("broken", "-DPCL_EXTRA=3");
        FAIL() << "a kernel with a syntax error built";
    } catch (const pcl::DeviceError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("broken.cl"), std::string::npos) << msg;
        EXPECT_NE(msg.find(testDevice().info().name), std::string::npos) << msg;
        EXPECT_NE(msg.find("-DPCL_EXTRA=3"), std::string::npos) << msg;
        EXPECT_NE(msg.find("pcl_undeclared_thing"), std::string::npos) << msg;
        // The #line markers point the log at the real file and line.
        EXPECT_NE(msg.find("broken.cl:3:"), std::string::npos) << msg;
    }
    EXPECT_TRUE(fs::is_empty(cache.path()));
}

// PHOTONCL_KERNEL_DIR switches every Device to sources on disk.
TEST(ProgramCache, KernelDirOverrideReadsFromDisk) {
    TempDir kernels, cache;
    writeFile(kernels.path() / "answer.cl", "__kernel void answer_write(__global uint* x) { x[0] = 42u; }\n");
    const char* old = std::getenv("PHOTONCL_KERNEL_DIR");
    const std::string keep = old ? old : "";
    setenv("PHOTONCL_KERNEL_DIR", kernels.path().c_str(), 1);
    ASSERT_TRUE(pcl::kernelDirOverride());
    EXPECT_EQ(*pcl::kernelDirOverride(), kernels.path());
    ProgramCache programs(testDevice().context(), testDevice().info(), pcl::kernelDirOverride(), cache.path());
    // A Device opened now reads its sources there too (and its binaries go to PHOTONCL_CACHE_DIR).
    const char* oldCache = std::getenv("PHOTONCL_CACHE_DIR");
    const std::string keepCache = oldCache ? oldCache : "";
    setenv("PHOTONCL_CACHE_DIR", cache.path().c_str(), 1);
    pcl::Device fresh = pcl::Device::open(std::to_string(testDevice().info().index));
    oldCache ? setenv("PHOTONCL_CACHE_DIR", keepCache.c_str(), 1) : unsetenv("PHOTONCL_CACHE_DIR");
    old ? setenv("PHOTONCL_KERNEL_DIR", keep.c_str(), 1) : unsetenv("PHOTONCL_KERNEL_DIR");
    auto viaDevice = fresh.kernel<cl::Buffer>("answer", "answer_write");
    cl::Buffer one = fresh.allocate<uint32_t>(1);
    fresh.launch("answer", viaDevice, cl::NDRange(1), one);
    EXPECT_EQ(fresh.download<uint32_t>(one, 1)[0], 42u);
    EXPECT_FALSE(fs::is_empty(cache.path()));

    cl::KernelFunctor<cl::Buffer> k(programs.build("answer"), "answer_write");
    pcl::Device& dev = testDevice();
    cl::Buffer out = dev.allocate<uint32_t>(1);
    dev.launch("answer", k, cl::NDRange(1), out);
    EXPECT_EQ(dev.download<uint32_t>(out, 1)[0], 42u);
    // The embedded table has no such stage.
    EXPECT_THROW(pcl::kernelSource("answer", std::nullopt), pcl::DeviceError);
}

}  // namespace
