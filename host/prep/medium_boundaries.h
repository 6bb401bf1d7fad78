// Which medium lies on either side of every surface, and which one the camera is in: what a
// path needs to know which medium it travels through (pbrt-v4's MediumInterface, §11.4).
//
// A "volume shape" encloses space a path can be in: a shape with a medium (a sphere or a closed
// mesh, validateScene checks), or a transmissive one (dielectric or invisible boundary) that is a
// sphere or a closed, outward-facing mesh. Its inside holds its medium (none: vacuum, e.g. a
// glass ball in fog); its outside holds the inside medium of the smallest volume shape around
// it, else the scene's global medium. Every other surface (opaque, or a thin open pane) has the
// surrounding medium on both sides.
//
// Volume shapes must be nested or disjoint, not overlapping: containment is decided by one
// point of a shape (a sphere's centre, a mesh's first vertex) at shutter open.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "geometry/scene_geometry.h"
#include "scene/scene.h"

namespace pcl {

struct MediumBoundaries {
    std::vector<int32_t> inside, outside;  // per global primitive: Scene::media index or -1 (vacuum)
    int32_t cameraMedium = -1;             // the medium at the camera position

    // The medium a ray is in after leaving primitive `prim` along a direction whose dot with
    // the geometric normal is `cosGeometric` (< 0: into the inside).
    int32_t beyond(uint32_t prim, float cosGeometric) const {
        return cosGeometric < 0.0f ? inside[prim] : outside[prim];
    }
};

// Only meaningful when scene.hasMedia(); otherwise every entry is -1.
MediumBoundaries findMediumBoundaries(const Scene& scene, const SceneGeometry& geometry);

// The medium at point p: the inside medium of the smallest volume shape holding p, else the
// global medium (at shutter open).
int32_t mediumAt(const Scene& scene, Vec3 p);

}  // namespace pcl
