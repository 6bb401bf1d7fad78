// The environment light ("sky") as flat buffers for the photon methods' kernels and their twins
// (kernels/shared/environment.h reads them, on both sides): texels with the scale applied and
// the importance-sampling tables in float, plus the light entry that emits its photons.
#pragma once
#include <vector>

#include "scene/scene.h"
#include "shared/environment.h"
#include "shared/types.h"

namespace pcl {

struct EnvironmentBuffers {
    PclEnvironment environment{};  // width 0: no sky
    std::vector<float> data;       // never empty (one 0 in a scene without a sky: a valid buffer)
    Vec3 integral{0.0f};           // ∫ L dω per channel, in double then rounded (4π L for a constant sky)
};

EnvironmentBuffers buildEnvironmentBuffers(const Environment& environment);

// The sky's photon light entry (PCL_LIGHT_ENVIRONMENT): photons cross a disc of the scene's
// bounding-sphere radius R, perpendicular to their direction, centred on the sphere's centre
// and moved 2R back (as a directional light's). Through that disc the sky sends
//   Φ = π R² ∫ L(ω) dω   per channel
// (from each direction ω the disc, facing ω, passes L(ω) πR² per unit solid angle), so a
// constant sky L gives Φ = 4π² R² L.
PclLight environmentLight(const EnvironmentBuffers& sky, Vec3 centre, float radius);

}  // namespace pcl
