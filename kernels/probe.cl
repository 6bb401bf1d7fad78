/* probe.cl: reports sizeof of every shared buffer struct as the device compiler sees it.
 * out: sizes[i] for the structs in the order listed in host/device/probe.cpp. */
#include "shared/types.h"

__kernel void probe_sizes(__global uint* sizes) {
    sizes[0] = sizeof(PclRay);
    sizes[1] = sizeof(PclHit);
    sizes[2] = sizeof(PclBvhNode);
    sizes[3] = sizeof(PclTriPacket);
    sizes[4] = sizeof(PclSphere);
}
