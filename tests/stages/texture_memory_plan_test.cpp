// The memory plan counts the texture buffers DeviceScene uploads (pipeline/memory_plan): on a
// textured scene the planned bytes of the per-material descriptors, the texels and the triangle
// coordinates equal the bytes allocated, buffer by buffer (observed through
// Device::setAllocationObserver), and the texels take 12 bytes each (three floats).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "common/textured_scenes.h"
#include "device_fixture.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"

namespace pcl {
namespace {

TEST(TextureMemoryPlan, TextureBuffersArePlannedToTheByte) {
    const Scene scene = test_scenes::texturedRoom();
    const SceneGeometry geometry = SceneGeometry::build(scene);
    const SceneBuffers buffers = buildSceneBuffers(scene, geometry);
    Device device = test::testDevice();
    std::map<std::string, size_t> allocated;
    device.setAllocationObserver([&](const std::string& what, size_t bytes) { allocated[what] = bytes; });
    PhotonPassOptions o;
    o.globalPhotons = 2000;
    o.buildCaustic = false;
    runPhotonPass(device, geometry, buffers, o);
    device.setAllocationObserver(nullptr);

    const MemoryPlan plan = planMemory(photonPassMemoryRequest(geometry, buffers, o), memoryLimits(device.info()));
    size_t texels = 0;
    for (const Texture& t : scene.textures) texels += t.image.pixelCount();
    const std::map<std::string, size_t> expected = {
        {"scene: material textures", scene.materials.size() * sizeof(PclMaterialTextures)},
        {"scene: texels", texels * 3 * sizeof(float)},
        {"scene: triangle texture coordinates", geometry.triangleCount() * sizeof(PclTriangleUv)}};
    for (const auto& [what, bytes] : expected) {
        const PlannedBuffer* b = plan.find("scene", what);
        ASSERT_NE(b, nullptr) << what << " is not planned";
        ASSERT_TRUE(allocated.count(what)) << what << " was never allocated";
        EXPECT_EQ(b->bytes, bytes) << what;
        EXPECT_EQ(allocated[what], bytes) << what;
        std::printf("[figure] %s: planned %zu bytes, allocated %zu bytes\n", what.c_str(), b->bytes, allocated[what]);
    }
}

}  // namespace
}  // namespace pcl
