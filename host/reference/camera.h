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

// A scene point seen by the camera (light tracing's connection to the camera, pbrt-v4's
// PerspectiveCamera::SampleWi): the pixel its light lands in, the lens point it reaches, and the
// factor that turns radiance leaving the point toward the lens into that pixel's estimate.
struct CameraConnection {
    int x = 0, y = 0;  // the pixel (y = 0 the top row)
    Vec3 lensPoint;    // the pinhole, or the sampled point on the thin lens
    // We(lens, ω) G_camera / p_lens without the cosine at the scene point: 1 / (A_pixel cos³θ d²),
    // A_pixel a pixel's area on the film plane at distance 1, θ the angle to the view axis, d
    // the distance from the point to the lens point. Over the pixel and the lens this integrates
    // the radiance to the pixel's average, the measurement generateRay's samples estimate.
    float importance = 0.0f;
};

class RayCamera {
public:
    explicit RayCamera(const Camera& camera);

    // The primary ray through pixel (x, y) (y = 0 the top row). Its direction is unit length,
    // tmin = 0, tmax = +inf, time = τ if the shutter is open for a while, otherwise 0.
    PclRay generateRay(int x, int y, const CameraSample& sample) const;

    // The camera as seen from scene point p, through lens point (lensU, lensV) (ignored by a
    // pinhole). False if p is behind the camera or its light falls outside the film.
    bool connect(Vec3 p, float lensU, float lensV, CameraConnection& out) const;
    // True if the shutter is open for a while: rays then carry a time τ in [0, 1).
    bool hasShutter() const { return shutterOpen_; }

private:
    Camera camera_;
    Vec3 forward_, right_, up_;
    float tanHalfHeight_, tanHalfWidth_;
    float pixelArea_;  // on the film plane at distance 1
    bool shutterOpen_;
};

}  // namespace pcl
