#include "reference/camera_rays.h"

#include "reference/camera.h"
#include "reference/parallel_for.h"
#include "reference/sampler.h"

namespace pcl {

std::vector<PclRay> referenceCameraRays(const Camera& camera, const PclCameraParams& params) {
    Camera cam = camera;
    if (!params.lensSampling) cam.model = CameraModel::Pinhole;  // the plan does not sample the lens
    const RayCamera rc(cam);
    const uint64_t seed = uint64_t(params.seedLo) | uint64_t(params.seedHi) << 32;
    const uint32_t n = params.strata, spp = n * n;
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
        cs.time = params.timeSampling ? sampler.get(CameraDims::kTime) : 0.0f;
        rays[i] = rc.generateRay(int(pixel % params.width), int(pixel / params.width), cs);
    });
    return rays;
}

}  // namespace pcl
