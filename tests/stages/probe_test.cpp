// Host and device agree on the shared headers: struct sizes (types.h) and Philox4x32-10 (rng.h).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <regex>
#include <set>

#include "device/probe.h"
#include "device_fixture.h"
#include "shared/rng.h"

namespace {

TEST(Probe, DeviceStructSizesEqualHost) {
    const auto& structs = pcl::sharedStructs();
    std::vector<uint32_t> device = pcl::probeDeviceSizes(pcl::test::testDevice());
    ASSERT_EQ(device.size(), structs.size());
    for (size_t i = 0; i < structs.size(); ++i)
        EXPECT_EQ(device[i], structs[i].hostSize) << structs[i].name << " on " << pcl::test::testDevice().info().name;
}

// The probe is only as good as its list: every struct types.h (and environment.h, the sky's
// header) defines must be in it.
TEST(Probe, EveryStructInTypesHIsProbed) {
    std::string text;
    for (const char* header : {"/types.h", "/environment.h"}) {
        std::ifstream in(std::string(PHOTONCL_SOURCE_DIR "/kernels/shared") + header);
        ASSERT_TRUE(in) << header;
        text += std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    std::set<std::string> listed;
    for (const auto& s : pcl::sharedStructs()) listed.insert(s.name);
    static const std::regex def(R"(typedef\s+struct\s+(\w+))");
    int found = 0;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), def); it != std::sregex_iterator(); ++it) {
        ++found;
        EXPECT_TRUE(listed.count((*it)[1].str()))
            << (*it)[1].str() << " is defined in types.h but missing from PCL_SHARED_STRUCTS (struct_list.h)";
    }
    EXPECT_EQ(found, int(listed.size()));
}

// The Random123 known-answer vectors for philox4x32-10, evaluated by the device compiler.
TEST(Probe, DevicePhiloxKnownAnswers) {
    const std::vector<pcl::PhiloxInput> in = {
        {{0, 0, 0, 0}, {0, 0}},
        {{0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, {0xffffffff, 0xffffffff}},
        {{0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}, {0xa4093822, 0x299f31d0}},
    };
    const std::array<uint32_t, 4> expected[] = {
        {0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8},
        {0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd},
        {0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1},
    };
    auto out = pcl::probeDevicePhilox(pcl::test::testDevice(), in);
    ASSERT_EQ(out.size(), in.size());
    for (size_t i = 0; i < in.size(); ++i)
        for (int j = 0; j < 4; ++j) EXPECT_EQ(out[i][j], expected[i][j]) << "vector " << i << " word " << j;
}

// The device walks the same (seed, path, bounce, stream, dimension) layout as the host.
TEST(Probe, DeviceRngStreamEqualsHost) {
    const uint64_t seed = 0xFEDCBA9876543210ull;
    const size_t n = 41;
    auto device = pcl::probeDeviceRngStream(pcl::test::testDevice(), seed, 123456, 7, PCL_RNG_STREAM_GATHER, n);
    PclRng r = rng_start(seed, 123456, 7, PCL_RNG_STREAM_GATHER);
    for (size_t d = 0; d < n; ++d) EXPECT_EQ(device[d], rng_next_u32(&r)) << "dimension " << d;
}

}  // namespace
