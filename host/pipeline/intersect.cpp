#include "pipeline/intersect.h"

#include <algorithm>

namespace pcl {

DeviceGeometry::DeviceGeometry(Device& device, const SceneGeometry& g)
    : nodes(device.upload(g.nodes, CL_MEM_READ_ONLY, "scene: BVH nodes")),
      packets(device.upload(g.packets, CL_MEM_READ_ONLY, "scene: triangle packets")),
      spheres(device.upload(g.spheres, CL_MEM_READ_ONLY, "scene: spheres")) {
    // Round up so trees of similar depth share one compiled program.
    stackSize = std::max(16, (g.stats().maxStack + 15) / 16 * 16);
}

std::string DeviceGeometry::programOptions() const { return "-DPCL_BVH_STACK_SIZE=" + std::to_string(stackSize); }

void intersectBuffers(Device& device, const DeviceGeometry& geometry, const cl::Buffer& rays, cl::Buffer& hits,
                      size_t n, bool anyHit) {
    auto kernel = device.kernel<cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl::Buffer, cl_uint, cl_uint>(
        "intersect", anyHit ? "intersect_any" : "intersect_closest", geometry.programOptions());
    for (size_t first = 0; first < n; first += kIntersectChunk) {
        size_t count = std::min(kIntersectChunk, n - first);
        device.launch("intersect", kernel, cl::NDRange(count), rays, geometry.nodes, geometry.packets, geometry.spheres,
                      hits, static_cast<cl_uint>(first), static_cast<cl_uint>(count));
    }
}

}  // namespace pcl
