// Camera rays of the reference path tracer: pinhole or thin lens (pbrt-v4 §5.2), a jittered
// point in the pixel, and a shutter time for motion blur.
#pragma once
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct CameraSample {
    float filmX = 0.5f, filmY = 0.5f;  // position inside the pixel, [0,1)^2
    float lensU = 0.5f, lensV = 0.5f;  // [0,1)^2, mapped to the aperture disk
    float time = 0.0f;                 // [0,1): the normalised shutter time τ
};

class RayCamera {
public:
    explicit RayCamera(const Camera& camera);

    // The primary ray through pixel (x, y) (y = 0 the top row). Its direction is unit length,
    // tmin = 0, tmax = +inf, time = τ if the shutter is open for a while, otherwise 0.
    PclRay generateRay(int x, int y, const CameraSample& sample) const;

private:
    Camera camera_;
    Vec3 forward_, right_, up_;
    float tanHalfHeight_, tanHalfWidth_;
    bool shutterOpen_;
};

}  // namespace pcl
