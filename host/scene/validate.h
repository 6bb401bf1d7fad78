// Whole-scene checks after loading, whatever the file format, plus the two repairs every
// renderer relies on: degenerate triangles are dropped (counted, with a warning) and every
// emissive mesh has a Light{Area} entry, so light sampling finds all emitters.
#pragma once
#include "scene/scene.h"

namespace pcl {

// Throws InputError naming scene.path and the offending element (materials[i], meshes[i],
// spheres[i], lights[i], camera) when the scene cannot be rendered as the file says.
void validateScene(Scene& scene);

}  // namespace pcl
