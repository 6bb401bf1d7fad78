// Stage 2 of the photon pass: photon paths with Russian roulette, a record deposited into the
// path's slots at every diffuse hit (kernels/trace_photons.cl, spec in kernels/README.md
// "trace_photons"). The twin is host/reference/trace_photons.cpp.
#pragma once
#include <vector>

#include "device/device.h"
#include "pipeline/device_scene.h"
#include "shared/types.h"

namespace pcl {

// Paths per batch: at most 2^18 on a GPU (every SM busy, a launch well under 0.5 s) and 2^16
// on a CPU, fewer when the slot buffer (paths × slots × 24 bytes) would pass a quarter of the
// device's largest allocation (capped by --max-buffer-mib) or 256 MiB; whole 1024s, or whole
// work-groups of 64 under a cap of a few MiB.
uint32_t defaultPhotonBatch(const Device& device, uint32_t slotsPerPath);
// The same from the limits alone (the memory plan sizes batches before there is a Device).
uint32_t defaultPhotonBatch(size_t maxAlloc, bool gpu, uint32_t slotsPerPath);

// Slots per path: maxDepth in either pass (one record per hit at most; a caustic path can
// deposit at several hits when it bounces specularly off mixed surfaces).
uint32_t photonSlotsPerPath(const PclPhotonParams& params);

// Enqueues trace_photons_global or trace_photons_caustic (by params.pass) over
// params.batchSize paths: rays in, slots (photonSlotsPerPath × batchSize, slot-major: record k of
// path i at k*batchSize + i), counts and ends (batchSize each) out; in a scene with media
// (params.hasMedia) also the volume photons in volumeSlots/volumeCounts, laid out as slots/counts
// (otherwise these are never touched and may be one-element placeholders).
cl::Event tracePhotons(Device& device, const DeviceScene& scene, const PclPhotonParams& params, const cl::Buffer& rays,
                       cl::Buffer& slots, cl::Buffer& counts, cl::Buffer& ends, cl::Buffer& volumeSlots,
                       cl::Buffer& volumeCounts);

}  // namespace pcl
