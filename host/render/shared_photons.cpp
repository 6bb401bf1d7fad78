#include "render/shared_photons.h"

#include <stdexcept>
#include <string>

namespace pcl {

PassPhotons SharedPhotonStages::tracePhotons(const PhotonPassOptions& options) {
    if (mode_ == Mode::Record) {
        PassPhotons p = inner_.tracePhotons(options);
        record_[options.pass] = p;
        return p;
    }
    auto it = record_.find(options.pass);
    if (it == record_.end())
        throw std::logic_error("shared photons: pass " + std::to_string(options.pass) + " was not recorded");
    const PassPhotons& p = it->second;
    // The recording render's photon counts must be these (a map it did not build emitted none).
    const uint64_t global = options.buildGlobal ? options.globalPhotons : 0,
                   caustic = options.buildCaustic ? options.causticPhotons : 0;
    if ((p.globalEmitted != 0 && p.globalEmitted != global) || (p.causticEmitted != 0 && p.causticEmitted != caustic))
        throw std::logic_error("shared photons: pass " + std::to_string(options.pass) +
                               " was recorded with other photon counts");
    return p;
}

}  // namespace pcl
