// Stage 1 of the photon pass: photons leave the lights (kernels/emit.cl, spec in
// kernels/README.md "emit"). The twin is host/reference/emit.cpp.
#pragma once
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "shared/types.h"

namespace pcl {

// Enqueues emit_photons for the batch params describes: rays[i] for photon
// params.firstPhoton + i, i < params.batchSize. lightFirst is the pass's lightFirstPhoton on the
// device. Returns the launch's event (empty for an empty batch).
cl::Event emitPhotons(Device& device, const DeviceScene& scene, const cl::Buffer& lightFirst,
                      const PclPhotonParams& params, cl::Buffer& rays);

}  // namespace pcl
