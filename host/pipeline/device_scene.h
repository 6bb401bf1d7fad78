// The scene on a device for the photon pass: the BVH (DeviceGeometry) and the flat shading
// buffers (SceneBuffers), uploaded once and read by emit and trace_photons.
#pragma once
#include "device/device.h"
#include "pipeline/intersect.h"
#include "prep/scene_buffers.h"

namespace pcl {

// Work-group size of every photon-pass launch, the global size rounded up to it (the kernels
// skip work-items past the batch). Fixed because PoCL compiles a kernel for each work-group
// size on its first launch: a size left to the runtime follows the batch size and recompiles.
constexpr size_t kPhotonGroup = 64;
inline cl::NDRange photonGlobalRange(size_t n) {
    return cl::NDRange((n + kPhotonGroup - 1) / kPhotonGroup * kPhotonGroup);
}

struct DeviceScene {
    DeviceScene(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers);
    DeviceGeometry geometry;
    cl::Buffer materials, primInfo, lights, projCells;
    // Media (SceneBuffers::hasMedia); one zeroed placeholder each in a scene without media, which
    // the kernels never read (PclPhotonParams::hasMedia = 0).
    cl::Buffer media, primMedia, lightMedia;
    // The sky (shared/environment.h): width 0 and one float of data without one.
    PclEnvironment sky;
    cl::Buffer skyData;
    // Textures (TextureBuffers): a descriptor per material; texels and triangle coordinates are
    // one-element placeholders in a scene without textures (every descriptor then has width 0).
    cl::Buffer materialTextures, texels, triangleUvs;
    // Shading normals (SceneBuffers::triangleNormals): a one-element placeholder when no
    // triangle is smooth.
    cl::Buffer triangleNormals;
    // Normal maps (NormalMapBuffers): one-element placeholders when no material has one.
    cl::Buffer normalMaps, triangleTangents;
    bool textured = false, smooth = false, normalMapped = false;
    // The options of the programs that read materials at hits (trace_photons, eye_paths,
    // final_gather): the BVH's, PCL_TEXTURED when the scene has textures, PCL_SHADING_NORMALS
    // when it has smooth triangles and PCL_NORMAL_MAPPED when it has normal maps, so other
    // scenes run the same code as before those existed (kernels/shared/texture.h,
    // kernels/shared/shading_frame.h).
    std::string programOptions() const {
        return geometry.programOptions() + (textured ? " -DPCL_TEXTURED=1" : "") +
               (smooth ? " -DPCL_SHADING_NORMALS=1" : "") + (normalMapped ? " -DPCL_NORMAL_MAPPED=1" : "");
    }
};

}  // namespace pcl
