/* shutter_open.h: where the global photon map keeps the photons of surfaces that move (scenes
 * with motion blur). A photon that lands on a moving primitive at shutter time τ is stored at
 * p − m τ, the point where that bit of surface sits when the shutter opens, and a global-map
 * query at a moving surface's point p (eye or gather hit, time τ) asks there too. The surface's
 * photons then lie on one surface instead of smeared along its path, where a query at any one
 * time found a fraction of them (motion-dof: the moving red ball's light on the floor read 2–4 %
 * too little red). Static surfaces (m = 0) keep p. The caustic map stays where its photons
 * landed (connect_caustics finds each record's surface again from there); the twins:
 * host/reference/shutter_open.h. */
#ifndef PCL_SHUTTER_OPEN_H
#define PCL_SHUTTER_OPEN_H
#ifdef __OPENCL_VERSION__

#include "types.h"
#include "sampling.h"

/* info: the primitive p lies on (the caller has loaded it already for its normal or material). */
inline PclV3 shutter_open_position(const PclPrimInfo info, PclV3 p, float tau) {
    return sampling_v3(p.x - info.mx * tau, p.y - info.my * tau, p.z - info.mz * tau);
}

#endif
#endif
