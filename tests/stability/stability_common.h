// Shared by the stability suite: a scene prepared for the photon renderer, and
// the small helpers every test uses. One Device per process (stages/device_fixture.h).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "accuracy/accuracy_common.h"
#include "common/prepared_render.h"
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

using test::expectFinite;
using test::prepare;
using test::Prepared;
using test::prepareFile;
using test::render;

inline double channelSum(const Image& img) {
    double s = 0.0;
    for (float v : img.rgb) s += v;
    return s;
}

}  // namespace pcl::stability
