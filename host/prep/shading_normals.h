// The per-triangle vertex normals the kernels and the twin interpolate for shading
// (kernels/shared/shading_frame.h, PclTriangleNormals).
//
// A triangle whose three vertex normals all lie along its face normal (within 1e-6 in the cosine)
// keeps zeros, so it shades with the geometric normal exactly: flat meshes exported with normals
// (every glTF from Blender) cost nothing and render as before. When no triangle is smooth the
// vector is empty and no buffer is uploaded (DeviceScene: no PCL_SHADING_NORMALS).
#pragma once
#include <vector>

#include "geometry/scene_geometry.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

// By global primitive id below geometry.triangleCount(); empty when no triangle is smooth.
std::vector<PclTriangleNormals> buildTriangleNormals(const Scene& scene, const SceneGeometry& geometry);

}  // namespace pcl
