#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "core/error.h"
#include "geometry/scene_geometry.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "reference/light_tracer.h"
#include "scene/load_scene.h"

namespace pcl::cli {

Run addCompareCommand(CLI::App& app) {
    struct Options {
        std::string test, reference, specularScene;
        double maxRmse = -1, maxRelMse = -1;
    };
    auto o = std::make_shared<Options>();
    CLI::App* sub =
        app.add_subcommand("compare", "Error of image A against reference B: RMSE, relMSE, mean ratio, max difference");
    sub->add_option("A", o->test,
                    "Test image (EXR, PNG, PFM); at n times B's width and height it is box-averaged n×n to B's "
                    "pixels first")
        ->required();
    sub->add_option("B", o->reference, "Reference image")->required();
    sub->add_option("--skip-specular-pixels", o->specularScene,
                    "SCENE: leave out the pixels whose camera rays (4x4 per pixel, pinhole) first hit a mirror or "
                    "glass, where a reference made by path and light tracing lacks the L S...S E light of point, "
                    "spot and directional lights (tests/data/references.md)");
    sub->add_option("--max-rmse", o->maxRmse, "Exit 1 when RMSE exceeds this");
    sub->add_option("--max-relmse", o->maxRelMse, "Exit 1 when relMSE exceeds this");
    return [o] {
        Image a = readImage(o->test), b = readImage(o->reference);
        // A render at n times the reference's size (256² against a 64-px reference) is compared
        // box-averaged to the reference's pixels; what the average hides is said.
        std::string averaged;
        if (a.width > b.width && b.width > 0 && a.width % b.width == 0 && a.height == b.height * (a.width / b.width)) {
            const int factor = a.width / b.width;
            a = boxDownsample(a, factor);
            averaged = " (A box-averaged " + std::to_string(factor) + "x" + std::to_string(factor) +
                       " to the reference's pixels)";
        }
        std::string masked;
        ImageErrors e;
        if (!o->specularScene.empty()) {
            Scene scene = loadScene(o->specularScene);
            scene.camera.width = b.width;
            scene.camera.height = b.height;
            const std::vector<uint8_t> keep = pixelsSeeingNoDeltaSurfaceFirst(scene, SceneGeometry::build(scene));
            size_t kept = 0;
            for (uint8_t k : keep) kept += k;
            masked = ", " + std::to_string(keep.size() - kept) + " pixels that see mirrors or glass first left out";
            e = compare(a, b, keep);
        } else {
            e = compare(a, b);
        }
        std::printf("%s vs %s (%dx%d)%s%s\n%s\n", o->test.c_str(), o->reference.c_str(), b.width, b.height,
                    averaged.c_str(), masked.c_str(), formatErrors(e).c_str());
        bool failed = (o->maxRmse >= 0 && !(e.rmse <= o->maxRmse)) ||
                      (o->maxRelMse >= 0 && !(e.relMse <= o->maxRelMse));
        if (failed) std::printf("FAILED: error above the stated bound\n");
        return failed ? kExitCheckFailed : kExitOk;
    };
}

}  // namespace pcl::cli
