// Shared by the stability suite: a scene prepared for the photon renderer, and
// the small helpers every test uses. One Device per process (stages/device_fixture.h).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "accuracy/accuracy_common.h"
#include "geometry/scene_geometry.h"
#include "image/image.h"
#include "image/metrics.h"
#include "prep/plan.h"
#include "prep/projection_map.h"
#include "prep/scene_buffers.h"
#include "render/photon_renderer.h"
#include "scene/validate.h"
#include "stages/device_fixture.h"
#include "stages/photon_test_scenes.h"

namespace pcl::stability {

// A scene with everything the renderer needs.
struct Prepared {
    Scene scene;
    std::unique_ptr<SceneGeometry> geometry;
    SceneBuffers buffers;
    LightPaths paths;
    RenderPlan plan;
};

inline std::unique_ptr<Prepared> prepare(Scene scene) {
    auto p = std::make_unique<Prepared>();
    p->scene = std::move(scene);
    p->geometry = std::make_unique<SceneGeometry>(SceneGeometry::build(p->scene));
    p->buffers = buildSceneBuffers(p->scene, *p->geometry);
    buildProjectionMaps(p->scene, *p->geometry, p->buffers);
    p->paths = classifyLightPaths(p->scene, *p->geometry, p->buffers);
    p->plan = makePlan(p->scene, p->paths);
    return p;
}

inline std::unique_ptr<Prepared> prepareFile(const std::string& name, int width, int height) {
    return prepare(accuracy::loadSceneAt(name, width, height));
}

inline PhotonRenderResult render(const Prepared& p, const PhotonRenderSettings& s) {
    return renderPhotonMapped(test::testDevice(), p.scene, *p.geometry, p.buffers, p.plan, s);
}

// No NaN or Inf in the film and no sample dropped for being non-finite.
inline void expectFinite(const PhotonRenderResult& r, const Image& img, const std::string& what) {
    size_t bad = 0;
    EXPECT_EQ(r.nonFiniteSamples, 0u) << what;
    EXPECT_TRUE(allFinite(img, &bad)) << what << ": pixel " << bad;
}

inline double channelSum(const Image& img) {
    double s = 0.0;
    for (float v : img.rgb) s += v;
    return s;
}

}  // namespace pcl::stability
