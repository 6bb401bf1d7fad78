// The photon-mapping renderer (the eye pass of kernels/README.md, then the film): a loop of
// passes, each one
//   photon pass (fresh photons, the pass index in the seed) → the maps the plan needs →
//   camera → eye paths (specular chains to the first diffuse hit) → at that hit:
//     fg:          direct light by shadow rays + caustic map + final gathering into the global map
//     direct:      the global map read at the hit (preview; its photons carry direct light too)
//     progressive: direct light + caustic map + the global map's indirect photons (those after a
//                  diffuse bounce), both read with a fixed radius that shrinks from pass to pass,
//                  r²_{i+1} = r²_i (i + α)/(i + 1) (Knaus & Zwicker 2011, probabilistic PPM)
//   → every sample's radiance (emitted + the parts above, summed by the accumulate stage; with
//     AOVs the parts come back apart and are summed here) added to the film.
// Eye samples are processed in chunks so the gather buffers stay within the device's max
// allocation. The film holds the average over the passes done; a stop request (Ctrl-C) is
// honoured between passes, so the film always holds whole passes.
// The stages run on an OpenCL device (renderPhotonMapped) or on the CPU twin
// (renderPhotonMappedTwin, host/reference): one loop calls either (render/render_stages.h), and
// the film is accumulated by the same host code, so the two renders of the same settings differ
// only where the stages do.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "image/film.h"
#include "image/fixed_point_film.h"
#include "pipeline/memory_plan.h"
#include "pipeline/photon_pass.h"
#include "prep/plan.h"
#include "prep/scene_buffers.h"
#include "render/render_settings.h"
#include "render/render_stages.h"
#include "scene/scene.h"

namespace pcl {

// Wall seconds per stage summed over the passes (each stage waits for its launches).
struct StageTimes {
    double photons = 0, maps = 0, camera = 0, eyePaths = 0, direct = 0, caustic = 0, indirect = 0, volume = 0,
           accumulate = 0, total = 0;
    std::string table() const;  // one "stage  seconds  share" line per stage
    StageTimes& operator+=(const StageTimes& t) {
        photons += t.photons, maps += t.maps, camera += t.camera, eyePaths += t.eyePaths, direct += t.direct;
        caustic += t.caustic, indirect += t.indirect, volume += t.volume, accumulate += t.accumulate;
        total += t.total;
        return *this;
    }
};

// Per-part films (RenderSettings::aovs): each part's radiance per sample, averaged like the film.
struct RenderAovs {
    Film direct, caustic, indirect, emitted, albedo, normal;
};

struct PhotonRenderResult {
    // Each pass is rendered into a Film of doubles and its per-pixel sums are rounded once to
    // 128-bit fixed point and added (image/fixed_point_film.h): integer sums do not depend on how
    // passes are grouped, so the same passes rendered in one run or as batch shards and merged
    // give the same bits. `film` is `sums` as doubles (for callers that merge or resolve films).
    FixedPointFilm sums;
    Film film;
    RenderAovs aovs;  // empty films unless settings.aovs
    StageTimes times;
    uint32_t passes = 0;   // passes done (the film holds exactly these)
    bool stopped = false;  // a stop request ended the render early
    // Photons over all passes.
    uint64_t globalEmitted = 0, causticEmitted = 0, globalStored = 0, causticStored = 0;
    // Each pass's photon pass, seconds (the first also loads the kernels and touches fresh buffers).
    std::vector<double> photonPassSeconds;
    uint64_t samples = 0;                   // eye samples traced
    uint64_t nonFiniteSamples = 0;          // samples whose radiance was NaN/Inf: dropped (expected 0)
    uint32_t emitterPixels = 0;             // fg: pixels given emitter samples (PhotonRenderSettings::emitterStrata)
    uint32_t emitterStrata = 0;             // fg: their M × M a pass (at most the setting's)
    float firstRadius = 0, lastRadius = 0;  // progressive: r_0 and the last pass's radius (global map)
    size_t chunkSamples = 0;
    std::string summary;  // the settings as used, one line (for logs and metadata)
};

// The photon pass of pass `pass` of a render with these settings: the maps the method builds
// (mapsFor; a map it does not build emits nothing), the photons per pass, the seed, the batch.
PhotonPassOptions photonPassOptions(const PhotonRenderSettings& s, const RenderPlan& plan, uint32_t pass = 0);
// The memory plan of one photon pass of that render on a device, checked before any work
// (InputError with advice when it cannot fit); its photonBatch is the batch to render with.
MemoryPlan planRenderMemory(const DeviceInfo& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                            const PhotonRenderSettings& s, const RenderPlan& plan);

// Total area of the scene's surfaces (triangles and spheres), for photon densities.
double sceneSurfaceArea(const Scene& scene);

// The progressive radius schedule: r²_i for pass i from r²_0 (Knaus & Zwicker 2011, eq. 13).
double progressiveRadius2(double r0Squared, double alpha, uint32_t pass);

// Renders scene.camera's image with the photon-mapping method settings.method (not
// PathTracing: that is render/path_render.h). `buffers` must hold the projection maps.
PhotonRenderResult renderPhotonMapped(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings);

// The same render on the CPU twin's stages: no OpenCL, the same seeds, pass structure and
// outputs (settings.photonBatch and chunkSamples are ignored: they change no pixel). The twin's
// searches are brute force: meant for small images (`render --device ref`, the render checks).
PhotonRenderResult renderPhotonMappedTwin(const Scene& scene, const SceneGeometry& geometry,
                                          const SceneBuffers& buffers, const RenderPlan& plan,
                                          const PhotonRenderSettings& settings);

// The same loop on any stages (a DeviceRenderStages or TwinRenderStages built for this scene
// and these settings, or one wrapped by render/shared_photons.h).
PhotonRenderResult renderPhotonMapped(RenderStages& stages, const Scene& scene, const SceneGeometry& geometry,
                                      const SceneBuffers& buffers, const RenderPlan& plan,
                                      const PhotonRenderSettings& settings);

}  // namespace pcl
