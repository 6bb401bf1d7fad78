// `check --stage emit`: photon emission, ray by ray, kernel against twin (photon_stages.h).
#include <algorithm>
#include <cmath>
#include <vector>

#include "check/on_device.h"
#include "check/photon_compare.h"
#include "check/photon_stages.h"
#include "core/clock.h"
#include "reference/emit.h"

namespace pcl {

void comparePhotonRays(const std::vector<PclPhotonRay>& host, const std::vector<PclPhotonRay>& dev, float radius,
                       PhotonCheckRow& row) {
    using namespace photon_check;
    for (size_t i = 0; i < host.size(); ++i) {
        const PclPhotonRay& h = host[i];
        const PclPhotonRay& d = dev[i];
        row.items++;
        const double eo = positionError(originOf(h), originOf(d), radius);
        const double ed = maxAbs(directionOf(h) - directionOf(d));
        const Vec3 ph(h.power[0], h.power[1], h.power[2]), pd(d.power[0], d.power[1], d.power[2]);
        const double ep = maxAbs(ph - pd) / std::max(maxComponent(ph), 1e-30f);
        row.maxOriginError = std::max(row.maxOriginError, eo);
        row.maxDirectionError = std::max(row.maxDirectionError, ed);
        row.maxPowerError = std::max(row.maxPowerError, ep);
        row.originMismatches += !(eo <= kPositionTolerance) || h.time != d.time;
        row.directionMismatches += !(ed <= kDirectionTolerance);
        row.powerMismatches += !(ep <= kPowerTolerance);
        row.lightMismatches += h.light != d.light;
    }
}

PhotonCheckReport checkEmit(Device& device, const SceneGeometry& geometry, const SceneBuffers& buffers,
                            const PhotonCheckOptions& options) {
    using namespace photon_check;
    return perPassReport(
        "emit", geometry, buffers, options, [&](const CheckPass& pass, PhotonCheckRow& row, PhotonCheckReport& report) {
            for (const PclPhotonParams& params : pass.batches) {
                auto t = Clock::now();
                const std::vector<PclPhotonRay> rays = emitPhotonsReference(buffers, pass.first, params);
                report.hostSeconds += since(t);
                t = Clock::now();
                const std::vector<PclPhotonRay> dev = emitOnDevice(device, geometry, buffers, pass.first, params);
                report.deviceSeconds += since(t);
                comparePhotonRays(rays, dev, buffers.sceneRadius, row);
            }
        });
}

}  // namespace pcl
