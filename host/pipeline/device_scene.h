// The scene on a device for the photon pass: the BVH (DeviceGeometry) and the flat shading
// buffers (SceneBuffers), uploaded once and read by emit and trace_photons.
#pragma once
#include "device/device.h"
#include "pipeline/intersect.h"
#include "pipeline/scene_buffers.h"

namespace pcl {

struct DeviceScene {
    DeviceScene(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers);
    DeviceGeometry geometry;
    cl::Buffer materials, primInfo, lights, projCells;
};

}  // namespace pcl
