// Kernel sources read from disk (PHOTONCL_KERNEL_DIR) are expanded exactly as the embedded
// ones, and the binary-cache key and paths follow their documented rules. No device needed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "device/embedded_kernels.h"
#include "device/program_cache.h"

namespace {

TEST(KernelSource, DiskExpansionEqualsEmbedded) {
    int n = 0;
    for (const pcl::EmbeddedKernel* k = pcl::kEmbeddedKernels; k->name; ++k, ++n)
        EXPECT_EQ(pcl::expandKernelFile(PHOTONCL_SOURCE_DIR "/kernels", k->name), std::string(k->source))
            << "kernels/" << k->name << ".cl: the C++ expansion differs from scripts/embed_kernels.py's "
            << "(or the kernel changed since this binary was built: rebuild)";
    EXPECT_GE(n, 1);
}

TEST(KernelSource, IncludesAreInlinedWithLineMarkers) {
    std::string s = pcl::expandKernelFile(PHOTONCL_SOURCE_DIR "/kernels", "probe");
    EXPECT_EQ(s.rfind("#line 1 \"probe.cl\"", 0), 0u);
    EXPECT_NE(s.find("#line 1 \"shared/types.h\""), std::string::npos);
    EXPECT_NE(s.find("#line 1 \"shared/rng.h\""), std::string::npos);
    EXPECT_EQ(s.find("#include \"shared/"), std::string::npos);
    // compat.h is included by several headers but inlined once.
    size_t first = s.find("#line 1 \"shared/compat.h\"");
    ASSERT_NE(first, std::string::npos);
    EXPECT_EQ(s.find("#line 1 \"shared/compat.h\"", first + 1), std::string::npos);
}

TEST(KernelSource, UnknownStageIsADeviceError) {
    EXPECT_THROW(pcl::kernelSource("no_such_stage", std::nullopt), pcl::DeviceError);
    EXPECT_THROW(pcl::kernelSource("no_such_stage", std::filesystem::path(PHOTONCL_SOURCE_DIR "/kernels")),
                 pcl::DeviceError);
}

// FNV-1a 64 reference values (the FNV authors' test suite).
TEST(KernelSource, Fnv1a64) {
    EXPECT_EQ(pcl::fnv1a64("", 0), 0xcbf29ce484222325ull);
    EXPECT_EQ(pcl::fnv1a64("a", 1), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(pcl::fnv1a64("foobar", 6), 0x85944171f73967e8ull);
}

TEST(KernelSource, CacheDirectoryFollowsEnvironment) {
    const char* saved[3] = {std::getenv("PHOTONCL_CACHE_DIR"), std::getenv("XDG_CACHE_HOME"), std::getenv("HOME")};
    std::string keep[3];
    for (int i = 0; i < 3; ++i) keep[i] = saved[i] ? saved[i] : "";
    auto restore = [&] {
        const char* names[3] = {"PHOTONCL_CACHE_DIR", "XDG_CACHE_HOME", "HOME"};
        for (int i = 0; i < 3; ++i) saved[i] ? setenv(names[i], keep[i].c_str(), 1) : unsetenv(names[i]);
    };
    setenv("HOME", "/home/someone", 1);
    unsetenv("PHOTONCL_CACHE_DIR");
    unsetenv("XDG_CACHE_HOME");
    EXPECT_EQ(pcl::cacheDirectory(), std::filesystem::path("/home/someone/.cache/photoncl"));
    setenv("XDG_CACHE_HOME", "relative/ignored", 1);
    EXPECT_EQ(pcl::cacheDirectory(), std::filesystem::path("/home/someone/.cache/photoncl"));
    setenv("XDG_CACHE_HOME", "/xdg", 1);
    EXPECT_EQ(pcl::cacheDirectory(), std::filesystem::path("/xdg/photoncl"));
    setenv("PHOTONCL_CACHE_DIR", "/tmp/pcl-cache", 1);
    EXPECT_EQ(pcl::cacheDirectory(), std::filesystem::path("/tmp/pcl-cache"));
    restore();
}

}  // namespace
