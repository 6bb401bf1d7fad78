// A scene made ready for the photon renderer in tests, and one render in any method: shared by
// the accuracy and stability suites (one Device per process: stages/device_fixture.h).
#pragma once
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "accuracy/accuracy_common.h"
#include "geometry/scene_geometry.h"
#include "image/metrics.h"
#include "prep/plan.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "reference/path_tracer.h"
#include "render/photon_renderer.h"
#include "scene/mesh_tangents.h"
#include "stages/device_fixture.h"

namespace pcl::test {

// The scene with everything the renderer needs (the geometry behind a pointer: the BVH does
// not move).
struct Prepared {
    Scene scene;
    std::unique_ptr<SceneGeometry> geometry;
    SceneBuffers buffers;
    LightPaths paths;
    RenderPlan plan;
};

// settings.skyCaustics false: as render prepares a scene for fg (prepareScene).
inline std::unique_ptr<Prepared> prepare(Scene scene, const PlanSettings& settings = {}) {
    auto p = std::make_unique<Prepared>();
    p->scene = std::move(scene);
    addMissingTangents(p->scene);  // what validateScene does for a loaded scene
    p->geometry = std::make_unique<SceneGeometry>(SceneGeometry::build(p->scene));
    p->buffers = buildSceneBuffers(p->scene, *p->geometry);
    buildProjectionMaps(p->scene, *p->geometry, p->buffers);
    p->paths = classifyLightPaths(p->scene, *p->geometry, p->buffers);
    p->plan = makePlan(p->scene, p->paths, settings);
    if (!p->plan.skyCausticPhotons) clearSkyProjection(p->buffers);
    return p;
}

// A shipped scene (scenes/NAME) at width × height.
inline std::unique_ptr<Prepared> prepareFile(const std::string& name, int width, int height,
                                             const PlanSettings& settings = {}) {
    return prepare(accuracy::loadSceneAt(name, width, height), settings);
}

inline PhotonRenderResult render(const Prepared& p, const PhotonRenderSettings& s) {
    return renderPhotonMapped(testDevice(), p.scene, *p.geometry, p.buffers, p.plan, s);
}

// No NaN or Inf in the film and no sample dropped for being non-finite.
inline void expectFinite(const PhotonRenderResult& r, const Image& img, const std::string& what) {
    size_t bad = 0;
    EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
    EXPECT_TRUE(allFinite(img, &bad)) << what << ": pixel " << bad;
}

// The image of method m: the photon renderer with s (s.method set to m), or for PathTracing the
// reference path tracer with pathSpp samples per pixel, seed pathSeed, on 2 threads. Checked
// finite either way.
inline Image renderImage(const Prepared& p, RenderMethod m, PhotonRenderSettings s, int pathSpp, uint64_t pathSeed,
                         const std::string& what) {
    if (m == RenderMethod::PathTracing) {
        PathTracerSettings pt;
        pt.samplesPerPixel = pathSpp;
        pt.seed = pathSeed;
        pt.threads = 2;
        Image img = PathTracer(p.scene, *p.geometry, pt).render().resolve();
        size_t bad = 0;
        EXPECT_TRUE(allFinite(img, &bad)) << what << " path: pixel " << bad;
        return img;
    }
    s.method = m;
    const PhotonRenderResult r = render(p, s);
    Image img = r.film.resolve();
    expectFinite(r, img, what + " " + renderMethodName(m));
    return img;
}

}  // namespace pcl::test
