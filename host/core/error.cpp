#include "core/error.h"

namespace pcl {

ExitReport exitReportFor(const std::exception& e) {
    if (dynamic_cast<const InputError*>(&e)) return {kExitBadInput, e.what()};
    if (dynamic_cast<const DeviceError*>(&e)) return {kExitInternal, std::string("device error: ") + e.what()};
    return {kExitInternal, std::string("internal error: ") + e.what()};
}

}  // namespace pcl
