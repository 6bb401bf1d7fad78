// `photoncl check SCENE --stage render`: every eye-pass stage on the device against its CPU twin
// with the same random numbers, on a small image (the scene's camera resized), one pass.
//
// Stages are compared one at a time on the SAME inputs (the device's output of the stage
// before), so a divergence is charged to the stage that made it: camera rays; eye paths (from
// the device rays); direct light, final gather, caustics, direct visualisation (from the device
// eye records; the maps from one device photon pass; the twin estimates by brute force). Then
// per pixel the sum emitted + direct + caustics + gather, device vs twin. The gather is also
// compared reading precomputed irradiance (the twin looks up the device's stored points), and
// importance-sampled (Jensen's incident-flux histograms: the histograms themselves, then the
// gather and direct light given the device's histograms).
// Last, the films: the whole renderer (render/photon_renderer.h) on the device against the same
// renderer on the twin's stages, one pass of fg (precomputed irradiance, importance-sampled
// gather when histogramCells > 0), direct and progressive, the twin given the device's photon
// pass (render/shared_photons.h: the photon pass is `check --stage pass`'s business), per pixel.
// A film pixel matches at the same tolerance, but the film rows pass with ≥ filmRequired of their
// pixels matching: a pixel is off when any of its eye or gather paths was sent the other way by
// a rounding at an edge, which the eye and gather rows allow each of their samples.
//
// A value matches when |d − t| ≤ tolerance · max(|d|, |t|) + 1e-6 · peak (peak: the stage's
// largest twin value, so values a millionth of the brightest count as equal); a sample (or
// pixel) matches when all its values do. A stage passes with ≥ `required` of its samples
// matching and no NaN/Inf on either side.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "pipeline/estimate.h"
#include "prep/prepared_scene.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

struct RenderCheckOptions {
    int width = 64, height = 48;  // the check's image (the camera's aspect follows it)
    uint32_t strata = 1;          // n × n samples per pixel
    uint32_t pass = 0;
    uint64_t seed = 1;
    uint32_t maxDepth = 8;        // eye path hits
    uint32_t lightSamples = 1;    // M
    uint32_t gatherRays = 8;      // N
    uint32_t k = 50;              // photons per estimate
    float radiusFraction = 0.1f;  // r_max / scene bounding-box diagonal
    uint32_t globalPhotons = 20000, causticPhotons = 20000;
    EstimateSettings estimate;    // filter etc. (structure: the device map's)
    uint32_t histogramCells = 8;  // G of the importance-sampled gather's rows (0: those rows left out)
    double tolerance = 1e-3;      // relative, per value
    double required = 0.999;      // fraction of samples that must match
    double filmRequired = 0.99;   // fraction of film pixels that must match (see above)
    bool films = true;            // the film rows (false: the stages and their pixel sum only)
    size_t worstShown = 5;
};

struct WorstSample {
    size_t index = 0;  // sample (or pixel) index
    double relError = 0.0;
    float device[3] = {0, 0, 0}, twin[3] = {0, 0, 0};
};

struct StageComparison {
    std::string stage;
    size_t compared = 0, matched = 0;
    size_t nonFinite = 0;  // samples with a NaN/Inf value on either side
    size_t nonzero = 0;    // samples whose twin value is not all zero
    double maxRelError = 0.0;
    std::vector<WorstSample> worst;  // largest relative errors first
    double deviceSeconds = 0.0, twinSeconds = 0.0;
    double ownRequired = 0.0;  // > 0: the fraction this stage needs instead of the report's
    double fraction() const { return compared ? double(matched) / double(compared) : 1.0; }
    bool passed(double required) const {
        return nonFinite == 0 && compared > 0 && fraction() >= (ownRequired > 0.0 ? ownRequired : required);
    }
};

// Compares n samples of `values` floats each (device vs twin). Used by the check and the
// stage tests.
StageComparison compareValues(const std::string& stage, const std::vector<float>& device,
                              const std::vector<float>& twin, size_t values, double tolerance, size_t worstShown);
StageComparison compareRadiance(const std::string& stage, const std::vector<PclRadiance>& device,
                                const std::vector<PclRadiance>& twin, double tolerance, size_t worstShown);
// Rays: origin, direction, time. Eye records: flags and prim must be equal (else the sample does
// not match), then position, normal, throughput, emitted.
StageComparison compareRays(const std::vector<PclRay>& device, const std::vector<PclRay>& twin, double tolerance,
                            size_t worstShown);
StageComparison compareEyeHits(const std::vector<PclEyeHit>& device, const std::vector<PclEyeHit>& twin,
                               double tolerance, size_t worstShown);

struct RenderCheckReport {
    std::vector<StageComparison> stages;  // camera, eye paths, direct, gather, caustics, direct vis, pixels,
                                          // films
    double required = 0.999, tolerance = 1e-3;
    int width = 0, height = 0;
    size_t globalPhotons = 0, causticPhotons = 0;
    bool passed() const;        // every stage passed
    std::string table() const;  // one line per stage, the worst samples, the tolerances
};

RenderCheckReport checkRender(Device& device, const Scene& scene, const RenderCheckOptions& options = {});
// The same on a prepared scene (prepareScene(scene): its image size does not matter).
RenderCheckReport checkRender(Device& device, const Scene& scene, const PreparedScene& prepared,
                              const RenderCheckOptions& options = {});

}  // namespace pcl
