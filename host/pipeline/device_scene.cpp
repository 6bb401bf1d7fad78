#include "pipeline/device_scene.h"

namespace pcl {

DeviceScene::DeviceScene(Device& device, const SceneGeometry& g, const SceneBuffers& b)
    : geometry(device, g), materials(device.upload(b.materials)), primInfo(device.upload(b.primInfo)),
      lights(device.upload(b.lights)), projCells(device.upload(b.projCells)) {}

}  // namespace pcl
