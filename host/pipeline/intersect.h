// The traversal kernel (kernels/intersect.cl) from the host: the scene's flat BVH uploaded once,
// and batches of rays traced in chunked launches.
#pragma once
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "shared/types.h"

namespace pcl {

// SceneGeometry's arrays on a device, and the build option sizing the traversal stack to the
// tree (BvhStats::maxStack, rounded up). Every kernel that includes shared/bvh.h is built with
// programOptions() so its stack fits the tree it traces.
struct DeviceGeometry {
    DeviceGeometry(Device& device, const SceneGeometry& geometry);
    cl::Buffer nodes, packets, spheres;
    int stackSize = 64;
    std::string programOptions() const;
};

// Rays per launch: keeps each launch short (a watchdog on a display GPU, responsiveness on a
// CPU) while still filling every compute unit.
constexpr size_t kIntersectChunk = 1 << 18;

// Traces n rays from `rays` into `hits` (both device buffers), closest hit or any hit.
// Enqueues only; a blocking download (or device.finish()) waits for it.
void intersectBuffers(Device& device, const DeviceGeometry& geometry, const cl::Buffer& rays, cl::Buffer& hits,
                      size_t n, bool anyHit);

}  // namespace pcl
