// `photoncl check SCENE --stage trace`: the traversal kernel against the host traversal on the
// same random rays. Closest hit: same primitive id and t within 1e-5 relative; any hit: the
// same answer to "is anything in (tmin, tmax)?".
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "scene/scene.h"

namespace pcl {

struct IntersectCheck {
    std::string rays;  // which ray set: "camera", "inside", "shadow"
    size_t count = 0;
    size_t hostHits = 0, deviceHits = 0;
    size_t primMismatches = 0;  // closest hit: different primitive (or hit vs miss)
    size_t tMismatches = 0;     // same primitive, t off by more than 1e-5 relative
    size_t anyMismatches = 0;   // any-hit existence differs
    double maxRelT = 0.0;       // largest relative t difference over agreeing hits
};

struct IntersectCheckReport {
    std::vector<IntersectCheck> rows;
    double hostSeconds = 0.0, deviceSeconds = 0.0;
    bool passed() const;        // every mismatch count is 0
    std::string table() const;  // printable, one line per ray set plus a total
};

// Random rays, `rays` in all, split evenly between camera rays (pinhole through random pixel
// positions at random shutter times), rays from random points inside the scene bounds in random
// directions, and shadow rays between random points of the bounds (finite tmax). Deterministic
// in `seed`.
std::vector<PclRay> checkRays(const Scene& scene, const Bounds3& bounds, size_t rays, uint64_t seed,
                              std::vector<std::string>* setOfRay = nullptr);

IntersectCheckReport checkIntersect(Device& device, const Scene& scene, size_t rays, uint64_t seed);
// The same on an already built geometry.
IntersectCheckReport checkIntersect(Device& device, const Scene& scene, const SceneGeometry& geometry, size_t rays,
                                    uint64_t seed);

}  // namespace pcl
