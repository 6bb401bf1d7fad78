#include "reference/camera_rays.h"

#include "reference/camera.h"
#include "reference/parallel_for.h"
#include "reference/sampler.h"
#include "shared/rng.h"
#include "shared/stratify.h"

namespace pcl {

std::vector<PclRay> referenceCameraRays(const Camera& camera, const PclCameraParams& params) {
    Camera cam = camera;
    if (!params.lensSampling) cam.model = CameraModel::Pinhole;  // the plan does not sample the lens
    const RayCamera rc(cam);
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    const uint32_t n = params.strata, spp = n * n, cells = stratify_cells(spp);
    // The pass's lens and time patterns (the kernel reads their cells from a table; the twin
    // permutes itself), shifted per pixel.
    uint32_t pattern[4];
    rng_block(seed, PCL_PASS_PATTERN_PATH, PCL_CAMERA_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_CAMERA, pattern);
    std::vector<PclRay> rays(params.sampleCount);
    parallelForEveryThread(rays.size(), [&](size_t i) {
        const uint32_t s = params.firstSample + uint32_t(i);
        const uint32_t pixel = s / spp, k = s % spp;
        Sampler sampler(seed, pixel, k);
        CameraSample cs;
        cs.filmX = (float(k % n) + sampler.get(CameraDims::kFilm)) / float(n);
        cs.filmY = (float(k / n) + sampler.get(CameraDims::kFilm + 1)) / float(n);
        cs.lensU = sampler.get(CameraDims::kLens);
        cs.lensV = sampler.get(CameraDims::kLens + 1);
        float time = sampler.get(CameraDims::kTime);
        if (params.lensSampling || params.timeSampling) {
            uint32_t shift[4], a, b;
            rng_block(seed, pixel, PCL_CAMERA_PATTERN_BOUNCE, 0, PCL_RNG_STREAM_CAMERA, shift);
            stratify_cmj_cell(k, spp, pattern[0], &a, &b);
            stratify_shifted(a, b, cells, spp, cs.lensU, cs.lensV, rng_u01(shift[0]), rng_u01(shift[1]), &cs.lensU,
                             &cs.lensV);
            float row;
            stratify_cmj_cell(k, spp, pattern[1], &a, &b);
            stratify_shifted(a, b, cells, spp, 0.5f, time, 0.0f, rng_u01(shift[2]), &row, &time);
        }
        cs.time = params.timeSampling ? time : 0.0f;
        rays[i] = rc.generateRay(int(pixel % params.width), int(pixel / params.width), cs);
    });
    return rays;
}

}  // namespace pcl
