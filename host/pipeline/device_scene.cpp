#include "pipeline/device_scene.h"

namespace pcl {

DeviceScene::DeviceScene(Device& device, const SceneGeometry& g, const SceneBuffers& b)
    : geometry(device, g), materials(device.upload(b.materials, CL_MEM_READ_ONLY, "scene: materials")),
      primInfo(device.upload(b.primInfo, CL_MEM_READ_ONLY, "scene: primitive info")),
      lights(device.upload(b.lights, CL_MEM_READ_ONLY, "scene: lights")),
      projCells(device.upload(b.projCells, CL_MEM_READ_ONLY, "scene: projection cells")),
      media(device.upload(b.hasMedia ? b.media : std::vector<PclMedium>(1), CL_MEM_READ_ONLY, "scene: media")),
      primMedia(device.upload(b.hasMedia ? b.primMedia : std::vector<PclPrimMedium>(1), CL_MEM_READ_ONLY,
                              "scene: primitive media")),
      lightMedia(
          device.upload(b.hasMedia ? b.lightMedia : std::vector<int32_t>(1), CL_MEM_READ_ONLY, "scene: light media")),
      sky(b.sky.environment), skyData(device.upload(b.sky.data, CL_MEM_READ_ONLY, "scene: environment")),

      materialTextures(device.upload(b.textures.materialTextures.empty() ? std::vector<PclMaterialTextures>(1)
                                                                         : b.textures.materialTextures,
                                     CL_MEM_READ_ONLY, "scene: material textures")),
      texels(device.upload(b.textures.textured() ? b.textures.texels : std::vector<float>(1), CL_MEM_READ_ONLY,
                           "scene: texels")),
      triangleUvs(device.upload(b.textures.textured() ? b.textures.triangleUvs : std::vector<PclTriangleUv>(1),
                                CL_MEM_READ_ONLY, "scene: triangle texture coordinates")),
      triangleNormals(device.upload(b.triangleNormals.empty() ? std::vector<PclTriangleNormals>(1) : b.triangleNormals,
                                    CL_MEM_READ_ONLY, "scene: triangle normals")),
      normalMaps(device.upload(b.normalMaps.mapped() ? b.normalMaps.maps : std::vector<PclNormalMap>(1),
                               CL_MEM_READ_ONLY, "scene: normal maps")),
      triangleTangents(
          device.upload(b.normalMaps.mapped() ? b.normalMaps.triangleTangents : std::vector<PclTriangleTangents>(1),
                        CL_MEM_READ_ONLY, "scene: triangle tangents")),
      textured(b.textures.textured()), smooth(!b.triangleNormals.empty()), normalMapped(b.normalMaps.mapped()) {}

}  // namespace pcl
