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

// NVIDIA's OpenCL ignores #line in its build log ("<kernel>:6:12: error: ..." on the H200): the
// host maps such numbers back through the markers, so a GPU's log names the file and line too.
TEST(KernelSource, BuildLogLinesOfTheExpandedSourceMapToTheirFiles) {
    const std::string source = "#line 1 \"broken.cl\"\n"                        // 1
                               "#line 1 \"shared/helper.h\"\n"                  // 2
                               "#define PCL_HELPER 1\n"                         // 3: helper.h:1
                               "#line 2 \"broken.cl\"\n"                        // 4
                               "__kernel void broken_run(__global int* x) {\n"  // 5: broken.cl:2
                               "    x[0] = pcl_undeclared_thing;\n"             // 6: broken.cl:3
                               "}\n";
    EXPECT_EQ(pcl::mapBuildLogLines("<kernel>:6:12: error: use of undeclared identifier\n<kernel>:3:9: note: x\n",
                                    source),
              "broken.cl:3:12: error: use of undeclared identifier\nshared/helper.h:1:9: note: x\n");
    // Already mapped (PoCL honours #line), out of range, or no line at all: unchanged.
    EXPECT_EQ(pcl::mapBuildLogLines("broken.cl:3:12: error: x", source), "broken.cl:3:12: error: x");
    EXPECT_EQ(pcl::mapBuildLogLines("<kernel>:99:1: error: x", source), "<kernel>:99:1: error: x");
    EXPECT_EQ(pcl::mapBuildLogLines("ptxas fatal", source), "ptxas fatal");
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
