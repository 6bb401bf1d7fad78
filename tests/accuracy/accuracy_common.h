// Shared by the accuracy tests against ground truth: the shipped scenes with their path-traced
// references in tests/data/ (made by scripts/make_references.py), loaded at the reference's size.
#pragma once
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "scene/load_scene.h"
#include "scene/scene.h"

namespace pcl::accuracy {

// Scene file names under scenes/ that have a reference, in tests/data/ref-<stem>.exr.
inline std::vector<std::string> referencedScenes() {
    return {"cornell-box.json", "cornell-spheres.json", "cornell-spheres-point.json", "cornell-glossy.json",
            "motion-dof.json",  "gltf-room.gltf",       "furnace-0.5.json",           "furnace-0.8.json"};
}

// The shipped scenes with participating media (scenes/media/), each with a path-traced reference
// in tests/data/ref-<stem>.exr. fg does not render media, so they are kept out of
// referencedScenes() (which the fg tests iterate) and out of scenes/ itself (which the tests over
// every shipped scene enumerate); their photon-method tests are media_render_test.cpp's; the
// path-traced reference tests take every list (pathTracedScenes()).
inline std::vector<std::string> mediaScenes() { return {"media/cornell-fog.json", "media/hazy-room.json"}; }

// The textured, sky-lit asset (scenes/courtyard/: a JSON scene, its glTF, textures and sky), with
// its reference like the others; its photon-method tests are courtyard_test.cpp's.
inline std::vector<std::string> texturedScenes() { return {"courtyard/courtyard.json"}; }

inline std::vector<std::string> pathTracedScenes() {
    std::vector<std::string> all = referencedScenes();
    for (const std::string& name : mediaScenes()) all.push_back(name);
    for (const std::string& name : texturedScenes()) all.push_back(name);
    return all;
}

inline std::string scenePath(const std::string& name) {
    return (std::filesystem::path(PHOTONCL_SOURCE_DIR) / "scenes" / name).string();
}

inline std::string referencePath(const std::string& sceneName) {
    return (std::filesystem::path(PHOTONCL_SOURCE_DIR) / "tests" / "data" /
            ("ref-" + std::filesystem::path(sceneName).stem().string() + ".exr"))
        .string();
}

// The scene with its camera resized to (width, height).
inline Scene loadSceneAt(const std::string& sceneName, int width, int height) {
    Scene scene = loadScene(scenePath(sceneName));
    scene.camera.width = width;
    scene.camera.height = height;
    return scene;
}

// ρ/(1−ρ): the furnace's radiance everywhere (scenes/furnace-*.json).
inline double furnaceRadiance(double rho) { return rho / (1.0 - rho); }

inline double meanValue(const Image& img) {
    double s = 0.0;
    for (float v : img.rgb) s += v;
    return img.rgb.empty() ? 0.0 : s / static_cast<double>(img.rgb.size());
}

}  // namespace pcl::accuracy
