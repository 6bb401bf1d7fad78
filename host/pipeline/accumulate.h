// The accumulate stage on the device (kernels/accumulate.cl): a chunk's eye records and parts
// summed into one radiance per sample, what the film adds. The host then reads 16 bytes a sample
// instead of the 128-byte record and every part: on a GPU that read-back, not the kernels, set
// a pass's time (an H200's fg pass at 256²: 18 ms of kernels, 90 ms reading the chunk back).
#pragma once

#include "device/device.h"
#include "shared/types.h"

namespace pcl {

// Enqueues accumulate_samples: radiance[i] (PclRadiance, caller-allocated, params.sampleCount)
// from hits and the parts params.parts names (the others may be any buffer: they are not read);
// spans holds 2 ints per image row when params.emitterSpans, else any buffer.
cl::Event accumulateSamples(Device& device, const PclAccumulateParams& params, const cl::Buffer& hits,
                            const cl::Buffer& direct, const cl::Buffer& caustic, const cl::Buffer& indirect,
                            const cl::Buffer& volume0, const cl::Buffer& volume1, const cl::Buffer& spans,
                            cl::Buffer& radiance);

}  // namespace pcl
