#include "pipeline/camera_rays.h"

#include <cmath>

#include "core/error.h"
#include "core/math.h"
#include "pipeline/device_scene.h"
#include "pipeline/pass_strata.h"
#include "shared/rng.h"

namespace pcl {

uint64_t eyePassSeed(uint64_t seed, uint32_t pass) { return seed + uint64_t(pass) * 0x9E3779B97F4A7C15ull; }

PclCameraParams cameraParams(const Camera& camera, bool lensSampling, bool timeSampling, uint64_t passSeed,
                             uint32_t strata) {
    if (strata < 1 || strata > 16)
        throw InternalError("camera rays: strata " + std::to_string(strata) +
                            ": expected 1..16 (n × n samples per pixel)");
    if (camera.width < 1 || camera.height < 1)
        throw InternalError("camera rays: image " + std::to_string(camera.width) + "×" + std::to_string(camera.height) +
                            ": expected at least one pixel");
    // The frame as reference/camera.cpp builds it.
    const Vec3 forward = normalize(camera.lookAt - camera.position);
    const Vec3 right = normalize(cross(forward, camera.up));
    const Vec3 up = cross(right, forward);
    const float tanHalfHeight = std::tan(0.5f * camera.vfovDegrees * kPi / 180.0f);
    const float tanHalfWidth = tanHalfHeight * static_cast<float>(camera.width) / static_cast<float>(camera.height);
    PclCameraParams p{};
    auto put = [](float* dst, Vec3 v) {
        dst[0] = v.x;
        dst[1] = v.y;
        dst[2] = v.z;
        dst[3] = 0.0f;
    };
    put(p.position, camera.position);
    put(p.forward, forward);
    put(p.right, right);
    put(p.up, up);
    p.tanHalfWidth = tanHalfWidth;
    p.tanHalfHeight = tanHalfHeight;
    p.apertureRadius = camera.apertureRadius;
    p.focusDistance = camera.focusDistance;
    p.seedLo = uint32_t(passSeed);
    p.seedHi = uint32_t(passSeed >> 32);
    p.width = uint32_t(camera.width);
    p.height = uint32_t(camera.height);
    p.strata = strata;
    p.firstSample = 0;
    const size_t total = size_t(camera.width) * size_t(camera.height) * strata * strata;
    if (total > 0xFFFFFFFFull)
        throw InputError("camera rays: " + std::to_string(total) + " samples in a pass: expected below 2^32");
    p.sampleCount = uint32_t(total);
    p.lensSampling = lensSampling && camera.model == CameraModel::ThinLens && camera.apertureRadius > 0.0f;
    p.timeSampling = timeSampling;
    return p;
}

PclCameraParams cameraParams(const Camera& camera, const RenderPlan& plan, uint64_t passSeed, uint32_t strata) {
    return cameraParams(camera, plan.lensSampling, plan.timeSampling, passSeed, strata);
}

cl::Event generateCameraRays(Device& device, const PclCameraParams& params, cl::Buffer& rays) {
    auto kernel = device.kernel<PclCameraParams, cl::Buffer, cl::Buffer>("camera", "camera_rays");
    // Two patterns: the lens points', then the shutter times'.
    const cl::Buffer strata = uploadPassStrata(device, params.seedLo, params.seedHi, PCL_RNG_STREAM_CAMERA,
                                               PCL_CAMERA_PATTERN_BOUNCE, 2, params.strata * params.strata,
                                               "camera: the pass's strata");
    return device.launchLocal("camera", kernel, photonGlobalRange(params.sampleCount), cl::NDRange(kPhotonGroup),
                              params, rays, strata);
}

}  // namespace pcl
