// Random numbers for the reference path tracer: Philox4x32-10 from kernels/shared/rng.h,
// indexed by (seed, pixel, sample, dimension), so an image does not depend on how pixels are
// spread over threads or shards.
//
// Counter layout: path = pixel index (y * width + x), the "bounce" word = sample index within
// the pixel, stream = PCL_RNG_STREAM_CAMERA, dimension = a fixed slot:
//   dimensions 0..4               camera: film x, film y, lens u, lens v, shutter time
//   dimensions 8+8b .. 8+8b+7    path vertex b: see PathVertexDims
// Fixed slots keep a vertex's numbers the same whatever the path did before it. A vertex is any
// event on the path: a surface hit, a scattering event in a medium, or the crossing of an
// invisible medium boundary. A scattering event in a medium uses the surface slots it needs
// (light choice and point, direction, roulette); kFreeFlight is the free-flight distance drawn on
// the segment that ends at the vertex (only in a medium), so it never meets the slots the vertex
// itself uses once it knows what it is.
// In a medium, each segment's equiangular sample (path_tracer.cpp) takes vertex slots 0 (which
// light) and 1 (the distance) of the segment's vertex on stream EQUIANGULAR.
// The light tracer (light_tracer.h) uses the same vertex slots on stream LIGHT_PATH, path = light
// path, bounce = pass.
#pragma once
#include <cstdint>

#include "shared/rng.h"

namespace pcl {

struct CameraDims {
    static constexpr uint32_t kFilm = 0, kLens = 2, kTime = 4;
};
struct PathVertexDims {
    static constexpr uint32_t kFirst = 8, kPerVertex = 8;
    static constexpr uint32_t kLightSelect = 0, kLightPoint = 1, kLobe = 3, kDirection = 4, kRoulette = 6,
                              kFreeFlight = 7;
};

class Sampler {
public:
    Sampler(uint64_t seed, uint32_t pixel, uint32_t sample, uint32_t stream = PCL_RNG_STREAM_CAMERA)
        : rng_(rng_start(seed, pixel, sample, stream)) {}

    // Uniform in [0, 1) at an absolute dimension.
    float get(uint32_t dim) {
        if (dim >> 2 != block_) {
            block_ = dim >> 2;
            rng_block(rng_.seed, rng_.path, rng_.bounce, block_, rng_.stream, words_);
        }
        return rng_u01(words_[dim & 3u]);
    }
    // The same pixel and sample on another stream: numbers a path draws besides its vertex slots
    // (the equiangular samples in media, PCL_RNG_STREAM_EQUIANGULAR, one vertex's worth per segment).
    Sampler withStream(uint32_t stream) const {
        Sampler other = *this;
        other.rng_.stream = stream;
        other.block_ = 0xFFFFFFFFu;
        return other;
    }
    // Dimension `k` of path vertex `vertex` (0: the camera ray's first hit).
    float vertex(uint32_t vertexIndex, uint32_t k) {
        return get(PathVertexDims::kFirst + PathVertexDims::kPerVertex * vertexIndex + k);
    }

private:
    PclRng rng_;
    uint32_t block_ = 0xFFFFFFFFu;
    uint32_t words_[4] = {0, 0, 0, 0};
};

}  // namespace pcl
