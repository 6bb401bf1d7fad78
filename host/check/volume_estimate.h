// `photoncl check SCENE --stage volume_estimate`: the device beam radiance estimate
// (pipeline/volume_estimate, kernels/volume_estimate.cl) against its CPU twin
// (reference/volume_estimate: its own cell map, candidates made unique, double sums) on the
// scene's own volume photons, for scenes with participating media.
//
// Photons: the device photon pass (global and caustic, `photons` paths each); each non-empty
// volume map is checked on its own, with its default radius over the photons in the scene's
// bounds (prep/volume_estimate_settings.h).
// Segments: camera rays through random pixels, from the camera in MediumBoundaries::cameraMedium,
// crossing invisible boundaries into the medium beyond, up to the first other surface (rays that
// leave the scene are dropped); one segment per medium stretch, throughput = the transmittance
// before it. Rows: map × kernel (box, biweight) × skipDirect (global map: off and on, with
// skipSpecularPaths on), and per map a row with per-photon radii (radiusK-th neighbour, clamped
// to [r/4, 2r] as the renderer does): the device's k-th neighbour distances (kd-tree search) must
// equal the twin's (grid) bit for bit, then the estimate is compared. A record matches when every channel agrees within kVolumeTolerance
// relative (float sums in the order found against double sums in photon order); a row passes
// when ≥ 99.9 % of records match (a photon at d ≈ r or t ≈ 0, ℓ may fall either side), none is
// NaN/Inf, and the twin sees nonzero radiance somewhere. A scene without media, or without
// volume photons, fails with the reason.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "prep/prepared_scene.h"
#include "prep/volume_estimate_settings.h"
#include "scene/scene.h"

namespace pcl {

struct VolumeEstimateCheckOptions {
    uint32_t photons = 50000;  // paths per photon pass (global and caustic each)
    uint32_t records = 4000;   // eye records (camera rays)
    uint32_t maxSegments = 4;  // segments per record
    uint32_t radiusK = 32;     // defaultVolumeRadius's k
    uint64_t seed = 1;
};

struct VolumeEstimateCheckRow {
    std::string map;              // "global volume" / "volume caustic"
    std::string kernel;           // "box" / "biweight"
    bool photonRadii = false;     // per-photon radii (else one radius for every photon)
    size_t radiusMismatches = 0;  // per-photon radii: photons whose k-th neighbour d² differs from the twin's
    bool skipDirect = false, skipSpecularPaths = false;
    size_t photons = 0, records = 0, segments = 0;
    float radius = 0.0f;
    size_t nonzero = 0;  // records the twin estimates nonzero
    size_t matched = 0;  // records within the tolerance
    size_t nans = 0;     // records with a non-finite value on either side
    double maxRelError = 0.0;
    double deviceSeconds = 0.0, twinSeconds = 0.0;
    double fraction() const { return records ? double(matched) / double(records) : 0.0; }
    bool passed() const;
};

struct VolumeEstimateCheckReport {
    std::vector<VolumeEstimateCheckRow> rows;
    std::string failure;  // set when nothing could be compared (no media, no volume photons)
    double photonSeconds = 0.0;
    bool passed() const;
    std::string table() const;
};

constexpr double kVolumeTolerance = 1e-4;
constexpr double kVolumeRequiredFraction = 0.999;

// Medium segments of camera rays (see above), `records` of them (some may hold 0 segments).
VolumeSegments cameraVolumeSegments(const Scene& scene, const SceneGeometry& geometry, uint32_t records,
                                    uint32_t maxSegments, uint64_t seed);

VolumeEstimateCheckReport checkVolumeEstimate(Device& device, const Scene& scene, const SceneGeometry& geometry,
                                              const SceneBuffers& buffers,
                                              const VolumeEstimateCheckOptions& options = {});

}  // namespace pcl
