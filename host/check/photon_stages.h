// `photoncl check SCENE --stage emit|trace|deposit` for the photon pass: each kernel stage
// against its CPU twin (host/reference/) on the same inputs, element by element.
//
//   emit     same params → same photon rays: origin within 1e-4 of max(|o|∞, scene radius),
//            direction within 1e-4 per component (absolute, unit vectors), power within 1e-5 of
//            the largest channel, light index equal. Fails on any mismatch.
//   trace    the twin's emitted rays fed to both → per path: end cause, bounce count and
//            deposit count equal; per deposit: position as for emit origins, packed bits
//            (direction bytes, bounce, flags) equal, RGBE within one mantissa step (decoded
//            channels within 2^(E − 136) of the larger exponent byte E). A path differing in
//            anything is divergent (float rounding can flip a rare decision); fails when more
//            than 0.1 % of paths diverge.
//   deposit  the twin's counts and slots fed to both → identical maps, byte for byte (also with
//            a map that must grow mid-check).
// Each stage runs a global pass and, when the scene's projection maps mark any cell, a caustic
// pass; the photons of each pass are split over two batches so firstPhoton ≠ 0 is exercised.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "check/on_device.h"
#include "device/device.h"
#include "geometry/scene_geometry.h"
#include "pipeline/trace_photons.h"
#include "prep/prepared_scene.h"
#include "prep/scene_buffers.h"
#include "reference/trace_photons.h"
#include "scene/scene.h"

namespace pcl {

struct PhotonCheckOptions {
    uint32_t photons = 50000;  // paths per pass (global and caustic each)
    uint32_t maxDepth = 16;
    uint64_t seed = 1;
    double maxDivergentFraction = 1e-3;  // trace: fail above 0.1 % divergent paths
};

// One line of a stage's table: one pass (global or caustic).
struct PhotonCheckRow {
    std::string pass;  // "global" / "caustic"
    size_t items = 0;  // photon rays or paths compared, or map records (deposit)
    // emit
    size_t originMismatches = 0, directionMismatches = 0, powerMismatches = 0, lightMismatches = 0;
    double maxOriginError = 0, maxDirectionError = 0, maxPowerError = 0;  // relative, as the tolerances
    // trace
    size_t deviceDeposits = 0, hostDeposits = 0;
    size_t divergent = 0;  // paths differing in any respect
    size_t endMismatches = 0, bounceMismatches = 0, countMismatches = 0;
    size_t positionMismatches = 0, packedMismatches = 0, rgbeMismatches = 0;
    double maxPositionError = 0;       // over deposits compared (paths with equal counts)
    size_t ends[5] = {0, 0, 0, 0, 0};  // twin's paths by PCL_END_* cause
    // deposit
    size_t byteMismatches = 0;  // records differing in any byte (or missing)
    uint32_t growths = 0;       // device map growths during the check
    // pass (whole photon pass; divergent, hostDeposits, deviceDeposits as for trace)
    size_t identicalRecords = 0;  // records of agreeing paths equal byte for byte
    size_t deviceBatches = 0;
    uint32_t slotsPerPath = 0;
};

struct PhotonCheckReport {
    std::string stage;  // "emit", "trace", "deposit" or "pass"
    std::vector<PhotonCheckRow> rows;
    double hostSeconds = 0.0, deviceSeconds = 0.0;
    double maxDivergentFraction = 1e-3;
    bool passed() const;
    std::string table() const;  // printable, one line per pass, then the verdict's reason
};

// stage: "emit", "trace", "deposit" or "pass". Prepares the scene itself (prepareScene). "pass" runs the whole photon pass both ways (pipeline/photon_pass with small device
// batches against reference/photon_pass) and aligns the two maps path by path with the twin's
// per-path deposit counts: a path agrees when its records match the device's at the aligned
// place within the trace tolerances; after a divergent path the device cursor resynchronises
// on the next path that matches within 2 S + 2 records. Fails above 0.1 % divergent paths, when
// the emitted path counts differ, or when the record counts differ by more than 0.1 % of the
// paths times S (paths the twin deposits nothing for can only diverge that way).
PhotonCheckReport checkPhotonStage(Device& device, const Scene& scene, const std::string& stage,
                                   const PhotonCheckOptions& options = {});
// The same on already built geometry and buffers (projection maps included, if wanted).
PhotonCheckReport checkPhotonStage(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                   const std::string& stage, const PhotonCheckOptions& options = {});

// The four stages, one file each (emit.cpp, trace_photons.cpp, deposit.cpp, pass.cpp), on built
// geometry and buffers; checkPhotonStage(stage) calls the one named.
PhotonCheckReport checkEmit(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                            const PhotonCheckOptions& options = {});
PhotonCheckReport checkTracePhotons(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                    const PhotonCheckOptions& options = {});
PhotonCheckReport checkDeposit(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                               const PhotonCheckOptions& options = {});
PhotonCheckReport checkPhotonPass(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                                  const PhotonCheckOptions& options = {});

// The comparisons themselves, added into `row` (tests feed them corrupted results to see the
// check fail). sceneRadius scales the position tolerance.
void comparePhotonRays(const std::vector<PclPhotonRay>& twin, const std::vector<PclPhotonRay>& device,
                       float sceneRadius, PhotonCheckRow& row);
void comparePhotonPaths(const ReferencePhotonBatch& twin, const PhotonTraceResult& device, float sceneRadius,
                        PhotonCheckRow& row);
void comparePhotonMaps(const std::vector<PclPhoton>& twin, const std::vector<PclPhoton>& device, PhotonCheckRow& row);

}  // namespace pcl
