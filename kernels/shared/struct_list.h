/* struct_list.h: every buffer struct of types.h, once, as an X-macro. kernels/probe.cl expands
 * it into device-side sizeof's and host/device/probe.cpp into host-side ones, so the two lists
 * cannot drift apart; tests/stages/probe_test.cpp checks that every `typedef struct` in types.h
 * is listed here. Add a struct to types.h → add it here. */
#ifndef PCL_STRUCT_LIST_H
#define PCL_STRUCT_LIST_H

#include "types.h"
#include "environment.h"

#define PCL_SHARED_STRUCTS(X) \
    X(PclRay)                 \
    X(PclHit)                 \
    X(PclBvhNode)             \
    X(PclTriPacket)           \
    X(PclSphere)              \
    X(PclMaterial)            \
    X(PclPrimInfo)            \
    X(PclMedium)              \
    X(PclPrimMedium)          \
    X(PclLight)               \
    X(PclPhotonRay)           \
    X(PclPhoton)              \
    X(PclPhotonParams)        \
    X(PclGridParams)          \
    X(PclKnnQuery)            \
    X(PclEstimateQuery)       \
    X(PclEstimateParams)      \
    X(PclEstimate)            \
    X(PclIrradiancePoint)     \
    X(PclCameraParams)        \
    X(PclEyeParams)           \
    X(PclVolumeSegment)       \
    X(PclEyeHit)              \
    X(PclRadiance)            \
    X(PclAccumulateParams)    \
    X(PclDirectParams)        \
    X(PclGatherParams)        \
    X(PclGatherHit)           \
    X(PclEyeEstimateParams)   \
    X(PclConnectParams)       \
    X(PclSplat)               \
    X(PclVolumeSegment)       \
    X(PclVolumeEstimateParams) \
    X(PclEnvironment)          \
    X(PclTexture)              \
    X(PclMaterialTextures)     \
    X(PclTriangleUv)           \
    X(PclTriangleNormals)      \
    X(PclNormalMap)            \
    X(PclTriangleTangents)

#endif /* PCL_STRUCT_LIST_H */
