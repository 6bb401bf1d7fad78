// Helpers for the eye-pass stage tests: shipped scenes resized, eye records made by hand, and
// an IrradianceSource of a constant irradiance (the analytic checks of the gather/estimates).
#pragma once
#include <string>
#include <vector>

#include "check/on_device.h"
#include "photon_test_scenes.h"
#include "pipeline/camera_rays.h"
#include "pipeline/eye_paths.h"
#include "pipeline/irradiance_source.h"

namespace pcl::test {

inline std::string shippedScenePath(const std::string& name) {
    return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name;
}

inline BuiltScene shippedScene(const std::string& name, int width, int height) {
    Scene s = loadScene(shippedScenePath(name));
    s.camera.width = width;
    s.camera.height = height;
    BuiltScene b = build(s);
    buildProjectionMaps(b.scene, b.geometry, b.buffers);
    return b;
}

// A diffuse eye record at p with viewer-side normal n (geometric and shading: a flat surface),
// throughput 1, albedo rho.
inline PclEyeHit handMadeHit(Vec3 p, Vec3 n, float rho, uint32_t pixel, uint32_t sample, uint32_t prim = 0) {
    PclEyeHit h{};
    h.x = p.x;
    h.y = p.y;
    h.z = p.z;
    h.nx = n.x;
    h.ny = n.y;
    h.nz = n.z;
    h.snx = n.x;
    h.sny = n.y;
    h.snz = n.z;
    h.wox = n.x;
    h.woy = n.y;
    h.woz = n.z;
    h.prim = prim;
    h.pixel = pixel;
    h.sample = sample;
    for (int c = 0; c < 3; ++c) {
        h.throughput[c] = 1.0f;
        h.albedo[c] = rho;
    }
    h.flags = PCL_EYE_DIFFUSE;
    return h;
}

// E = (e, e, e) wherever a query has maxRadius2 > 0 (float4 records); 0 elsewhere is not
// needed by the stages (a query without a hit has weight 0), so every record gets e.
inline IrradianceSource constantIrradiance(float e) {
    IrradianceSource s;
    s.name = "constant";
    s.strideFloats = 4;
    s.evaluate = [e](Device& device, const cl::Buffer&, size_t count) {
        cl::Buffer b = device.allocate<cl_float4>(count, CL_MEM_READ_WRITE, "test: constant irradiance");
        cl_float4 v;
        v.s[0] = v.s[1] = v.s[2] = e;
        v.s[3] = 0.0f;
        device.fill(b, v, count);
        device.finish();
        return b;
    };
    return s;
}

inline double meanLuminance(const std::vector<PclRadiance>& r) {
    double s = 0.0;
    for (const PclRadiance& x : r) s += (double(x.r) + x.g + x.b) / 3.0;
    return r.empty() ? 0.0 : s / double(r.size());
}

// The eye-path parameters of camera parameters cp on a built scene (its area-light table).
inline PclEyeParams eyeParamsFor(const PclCameraParams& cp, const BuiltScene& b) {
    return eyeParams(cp, b.geometry, b.buffers, buildAreaLightTable(b.buffers, b.geometry.primitiveCount()));
}

// Device camera rays and eye paths of a built scene (n × n strata, lens and time as the camera
// allows); the eye parameters in *params.
inline std::vector<PclEyeHit> deviceEyeHits(const BuiltScene& b, uint32_t strata, uint64_t passSeed,
                                            PclEyeParams* params = nullptr) {
    const PclCameraParams cp = cameraParams(b.scene.camera, true, true, passSeed, strata);
    const std::vector<PclRay> rays = cameraRaysOnDevice(testDevice(), cp);
    const PclEyeParams ep = eyeParamsFor(cp, b);
    if (params) *params = ep;
    return eyePathsOnDevice(testDevice(), b.geometry, b.buffers, rays, ep);
}

}  // namespace pcl::test
