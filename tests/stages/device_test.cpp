// Device choice, the program memo, buffers and the stage-named errors.
#include <gtest/gtest.h>

#include <sstream>

#include "device_fixture.h"

namespace {

using pcl::test::testDevice;

TEST(Device, ListsAtLeastOneDevice) {
    auto devices = pcl::listDevices();
    ASSERT_FALSE(devices.empty()) << "no OpenCL device: install pocl-opencl-icd (scripts/setup.sh)";
    for (size_t i = 0; i < devices.size(); ++i) {
        EXPECT_EQ(devices[i].index, int(i));
        EXPECT_FALSE(devices[i].name.empty());
        EXPECT_GT(devices[i].computeUnits, 0u);
        EXPECT_GT(devices[i].maxAlloc, 0u);
        EXPECT_LE(devices[i].maxAlloc, devices[i].globalMem);
    }
}

TEST(Device, PrintDevicesShowsEveryDevice) {
    std::ostringstream out;
    pcl::printDevices(out);
    for (const auto& d : pcl::listDevices()) {
        EXPECT_NE(out.str().find("[" + std::to_string(d.index) + "] " + d.name), std::string::npos) << out.str();
        EXPECT_NE(out.str().find(d.driver), std::string::npos);
    }
    EXPECT_NE(out.str().find("compute units"), std::string::npos);
    EXPECT_NE(out.str().find("max allocation"), std::string::npos);
}

TEST(Device, OpenBySpec) {
    auto devices = pcl::listDevices();
    ASSERT_FALSE(devices.empty());
    const auto& first = devices.front();
    EXPECT_EQ(pcl::Device::open("0").info().name, first.name);
    EXPECT_EQ(pcl::Device::open(first.name.substr(0, 6)).info().index, first.index);
    // Case-insensitive substring.
    std::string upper = first.name;
    for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(pcl::Device::open(upper).info().index, first.index);
    const pcl::DeviceInfo& a = testDevice().info();
    bool anyGpu = false;
    for (const auto& d : devices) anyGpu |= (d.type & CL_DEVICE_TYPE_GPU) != 0;
    if (!std::getenv("PHOTONCL_TEST_DEVICE")) {
        EXPECT_EQ((a.type & CL_DEVICE_TYPE_GPU) != 0, anyGpu) << "auto prefers a GPU";
    }
}

TEST(Device, UnknownSpecListsTheDevices) {
    for (const char* spec : {"no-such-device-zz", "99", "12345678901234567890"}) {
        try {
            pcl::Device::open(spec);
            FAIL() << spec << " opened a device";
        } catch (const pcl::DeviceError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(spec), std::string::npos) << msg;
            EXPECT_NE(msg.find(testDevice().info().name), std::string::npos) << msg;
        }
    }
}

TEST(Device, ProgramsAreMemoisedPerStageAndOptions) {
    pcl::Device& dev = testDevice();
    cl::Program a = dev.program("probe");
    cl::Program b = dev.program("probe");
    EXPECT_EQ(a(), b());
    cl::Program c = dev.program("probe", "-DPCL_PROBE_VARIANT=1");
    EXPECT_NE(a(), c());
    pcl::Device copy = dev;  // copies share the memo
    EXPECT_EQ(copy.program("probe")(), a());
}

TEST(Device, BuffersRoundTrip) {
    pcl::Device& dev = testDevice();
    std::vector<float> data = {1.5f, -2.0f, 3.25f};
    EXPECT_EQ(dev.download<float>(dev.upload(data), 3), data);
    std::vector<float> none;
    cl::Buffer empty = dev.upload(none);  // a valid one-element buffer
    EXPECT_TRUE(empty() != nullptr);
    cl::Buffer filled = dev.allocate<uint32_t>(5);
    dev.fill<uint32_t>(filled, 7u, 5);
    EXPECT_EQ(dev.download<uint32_t>(filled, 5), std::vector<uint32_t>(5, 7u));
}

TEST(Device, ErrorsNameTheStage) {
    try {
        testDevice().kernel<cl::Buffer>("probe", "probe_no_such_entry");
        FAIL();
    } catch (const pcl::DeviceError& e) {
        EXPECT_NE(std::string(e.what()).find("stage probe: CL_INVALID_KERNEL_NAME (-46)"), std::string::npos)
            << e.what();
    }
    try {
        pcl::Device::guard("trace", []() -> int { throw cl::Error(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel"); });
        FAIL();
    } catch (const pcl::DeviceError& e) {
        EXPECT_STREQ(e.what(), "stage trace: CL_OUT_OF_RESOURCES (-5) in clEnqueueNDRangeKernel");
    }
}

TEST(Device, LaunchWithLocalSize) {
    pcl::Device& dev = testDevice();
    auto k = dev.kernel<cl::Buffer, cl::Buffer, cl::Buffer>("probe", "probe_philox");
    std::vector<uint32_t> ctr(4 * 8, 0), key(2 * 8, 0);
    cl::Buffer c = dev.upload(ctr), kb = dev.upload(key), out = dev.allocate<uint32_t>(4 * 8);
    cl::Event e = dev.launchLocal("probe", k, cl::NDRange(8), cl::NDRange(4), c, kb, out);
    auto words = dev.download<uint32_t>(out, 4 * 8);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(words[4 * i], 0x6627e8d5u) << i;
    EXPECT_GE(pcl::Device::elapsedSeconds(e), 0.0);
}

TEST(Device, ZeroSizedLaunchIsSkipped) {
    pcl::Device& dev = testDevice();
    auto k = dev.kernel<cl::Buffer>("probe", "probe_sizes");
    cl::Buffer out = dev.allocate<uint32_t>(8);
    cl::Event e = dev.launch("probe", k, cl::NDRange(0), out);
    EXPECT_TRUE(e() == nullptr);
    EXPECT_EQ(pcl::Device::elapsedSeconds(e), 0.0);
}

}  // namespace
