#include "check/check_stages.h"

#include "check/estimate.h"
#include "check/eye_stages.h"
#include "check/knn.h"
#include "check/maps.h"
#include "check/photon_stages.h"
#include "check/precomputed_irradiance.h"
#include "check/render.h"
#include "check/trace.h"
#include "check/volume_estimate.h"

namespace pcl {
namespace {

template <class Report>
CheckReport toCheckReport(const std::string& stage, const Report& report) {
    CheckReport r;
    r.stage = stage;
    r.table = report.table();
    r.passed = report.passed();
    return r;
}

// emit, trace_photons, deposit and pass share their options and report (photon_stages.h).
template <PhotonCheckReport (*Check)(Device&, const SceneGeometry&, const SceneBuffers&, const PhotonCheckOptions&)>
std::vector<CheckReport> photonStage(const char* name, Device& device, const PreparedScene& prepared,
                                     const CheckOptions& o) {
    PhotonCheckOptions options;
    options.photons = o.photons;
    options.seed = o.seed;
    return {toCheckReport(name, Check(device, prepared.geometry, prepared.buffers, options))};
}
std::vector<CheckReport> emit(Device& d, const Scene&, const PreparedScene& p, const CheckOptions& o) {
    return photonStage<checkEmit>("emit", d, p, o);
}
std::vector<CheckReport> tracePhotons(Device& d, const Scene&, const PreparedScene& p, const CheckOptions& o) {
    return photonStage<checkTracePhotons>("trace_photons", d, p, o);
}
std::vector<CheckReport> deposit(Device& d, const Scene&, const PreparedScene& p, const CheckOptions& o) {
    return photonStage<checkDeposit>("deposit", d, p, o);
}
std::vector<CheckReport> pass(Device& d, const Scene&, const PreparedScene& p, const CheckOptions& o) {
    return photonStage<checkPhotonPass>("pass", d, p, o);
}

std::vector<CheckReport> trace(Device& device, const Scene& scene, const PreparedScene& prepared,
                               const CheckOptions& o) {
    return {toCheckReport("trace", checkIntersect(device, scene, prepared.geometry, o.rays, o.seed))};
}

MapCheckOptions mapOptions(const CheckOptions& o) {
    MapCheckOptions m;
    m.photons = o.photons;
    m.seed = o.seed;
    return m;
}

std::vector<CheckReport> sort(Device& device, const Scene&, const PreparedScene& prepared, const CheckOptions& o) {
    return {toCheckReport("sort", checkSort(device, prepared, mapOptions(o)))};
}

std::vector<CheckReport> build(Device& device, const Scene&, const PreparedScene& prepared, const CheckOptions& o) {
    return {toCheckReport("build", checkKdTreeBuild(device, prepared, mapOptions(o)))};
}

std::vector<CheckReport> knn(Device& device, const Scene& scene, const PreparedScene& prepared, const CheckOptions& o) {
    KnnCheckOptions options;
    options.photons = o.photons;
    options.seed = o.seed;
    return {toCheckReport("knn", checkKnn(device, scene, prepared.geometry, prepared.buffers, options))};
}

std::vector<CheckReport> estimate(Device& device, const Scene& scene, const PreparedScene& prepared,
                                  const CheckOptions& o) {
    EstimateCheckOptions options;
    options.photons = o.photons;
    options.seed = o.seed;
    IrradianceCheckOptions irradiance;
    irradiance.photons = o.photons;
    irradiance.seed = o.seed;
    return {toCheckReport("estimate", checkEstimate(device, scene, prepared.geometry, prepared.buffers, options)),
            toCheckReport("estimate (precomputed irradiance)",
                          checkPrecomputedIrradiance(device, scene, prepared.geometry, prepared.buffers, irradiance))};
}

RenderCheckOptions eyeOptions(const CheckOptions& o) {
    RenderCheckOptions options;
    options.seed = o.seed;
    return options;
}

std::vector<CheckReport> eyePaths(Device& device, const Scene& scene, const PreparedScene& prepared,
                                  const CheckOptions& o) {
    return {toCheckReport("eye_paths", checkEyePathsStage(device, scene, prepared, eyeOptions(o)))};
}

std::vector<CheckReport> directLight(Device& device, const Scene& scene, const PreparedScene& prepared,
                                     const CheckOptions& o) {
    return {toCheckReport("direct_light", checkDirectLightStage(device, scene, prepared, eyeOptions(o)))};
}

std::vector<CheckReport> connectCaustics(Device& device, const Scene& scene, const PreparedScene& prepared,
                                         const CheckOptions& o) {
    RenderCheckOptions options = eyeOptions(o);
    options.causticPhotons = o.photons;
    return {toCheckReport("connect_caustics", checkConnectCausticsStage(device, scene, prepared, options))};
}

std::vector<CheckReport> volumeEstimate(Device& device, const Scene& scene, const PreparedScene& prepared,
                                        const CheckOptions& o) {
    VolumeEstimateCheckOptions options;
    options.photons = o.photons;
    options.seed = o.seed;
    return {toCheckReport("volume_estimate",
                          checkVolumeEstimate(device, scene, prepared.geometry, prepared.buffers, options))};
}

std::vector<CheckReport> render(Device& device, const Scene& scene, const PreparedScene& prepared,
                                const CheckOptions& o) {
    RenderCheckOptions options;
    options.seed = o.seed;
    return {toCheckReport("render", checkRender(device, scene, prepared, options))};
}

}  // namespace

const std::vector<CheckStage>& checkStages() {
    static const std::vector<CheckStage> stages = {
        {"trace", "BVH traversal kernel against the host BVH traversal", "host BVH traversal", trace},
        {"emit", "photon emission, ray by ray", "CPU twin", emit},
        {"trace_photons", "photon tracing (Russian roulette, bounces, deposits), path by path", "CPU twin",
         tracePhotons},
        {"deposit", "the deterministic deposit into the maps, record by record", "CPU twin", deposit},
        {"pass", "the whole photon pass, maps aligned path by path", "CPU twin", pass},
        {"sort", "the device radix sort against a stable sort", "CPU twin", sort},
        {"build", "the kd-tree build, byte for byte and against its definition", "CPU twin", build},
        {"knn", "k nearest neighbours on kd-tree and hash grid against brute force", "CPU twin", knn},
        {"estimate",
         "the filtered irradiance estimate (every filter, both structures, with and without the visibility test) "
         "and the precomputed irradiance lookup",
         "CPU twin", estimate},
        {"eye_paths",
         "eye paths (specular chains; in media the transmittance, single scattering and the medium segments), "
         "record by record on a small image",
         "CPU twin", eyePaths},
        {"direct_light", "direct light at the eye records (shadow rays through media), record by record", "CPU twin",
         directLight},
        {"connect_caustics",
         "fg's caustic connections: each caustic photon joined to the camera, record by record, and their film "
         "(scenes with caustics)",
         "CPU twin", connectCaustics},
        {"volume_estimate",
         "the beam radiance estimate along camera-ray medium segments from the volume photon maps (scenes with "
         "media)",
         "CPU twin", volumeEstimate},
        {"render",
         "the eye pass (camera, eye paths, direct light, caustics, final gather, direct visualisation) per stage and "
         "per pixel on a small image",
         "CPU twin", render},
    };
    return stages;
}

}  // namespace pcl
