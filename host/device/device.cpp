#include "device/device.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <mutex>
#include <ostream>
#include <sstream>

#include "device/buffer_pool.h"
#include "device/program_cache.h"

namespace pcl {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

// Trailing NULs and spaces appear in some drivers' info strings.
std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
    return s;
}

std::string mib(size_t bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f MiB", double(bytes) / (1024.0 * 1024.0));
    return buf;
}

std::string summary(const std::vector<DeviceInfo>& devices) {
    if (devices.empty()) return "no OpenCL devices (is an ICD such as pocl-opencl-icd installed?)";
    std::ostringstream s;
    s << "available devices:";
    for (const DeviceInfo& d : devices)
        s << "\n  " << d.index << ": " << d.name << " (" << deviceTypeName(d.type) << ", " << d.platform << ")";
    return s.str();
}

}  // namespace

std::vector<DeviceInfo> listDevices() {
    std::vector<DeviceInfo> out;
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        return out;  // CL_PLATFORM_NOT_FOUND_KHR from the ICD loader: no platforms
    }
    for (cl::Platform& p : platforms) {
        std::vector<cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue;  // CL_DEVICE_NOT_FOUND: a platform with nothing usable
        }
        for (cl::Device& d : devices) {
            try {
                DeviceInfo info;
                info.index = static_cast<int>(out.size());
                info.platform = trimmed(p.getInfo<CL_PLATFORM_NAME>());
                info.platformVersion = trimmed(p.getInfo<CL_PLATFORM_VERSION>());
                info.name = trimmed(d.getInfo<CL_DEVICE_NAME>());
                info.vendor = trimmed(d.getInfo<CL_DEVICE_VENDOR>());
                info.version = trimmed(d.getInfo<CL_DEVICE_VERSION>());
                info.driver = trimmed(d.getInfo<CL_DRIVER_VERSION>());
                info.type = d.getInfo<CL_DEVICE_TYPE>();
                info.correctlyRoundedDivideSqrt =
                    (d.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
                info.computeUnits = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
                info.globalMem = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
                info.maxAlloc = d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
                info.driverMaxAlloc = info.maxAlloc;
                info.clPlatform = p;
                info.clDevice = d;
                out.push_back(std::move(info));
            } catch (const cl::Error&) {
                // A device that cannot describe itself cannot be used either: leave it out.
            }
        }
    }
    return out;
}

std::string deviceTypeName(cl_device_type type) {
    if (type & CL_DEVICE_TYPE_GPU) return "GPU";
    if (type & CL_DEVICE_TYPE_CPU) return "CPU";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

void printDevices(std::ostream& out) {
    std::vector<DeviceInfo> devices = listDevices();
    if (devices.empty()) {
        out << summary(devices) << "\n";
        return;
    }
    std::string platform;
    for (const DeviceInfo& d : devices) {
        if (d.platform != platform) {
            platform = d.platform;
            out << "Platform: " << d.platform << " (" << d.platformVersion << ")\n";
        }
        out << "  [" << d.index << "] " << d.name << "\n"
            << "      type:           " << deviceTypeName(d.type) << "\n"
            << "      vendor:         " << d.vendor << "\n"
            << "      version:        " << d.version << "\n"
            << "      driver:         " << d.driver << "\n"
            << "      compute units:  " << d.computeUnits << "\n"
            << "      global memory:  " << mib(d.globalMem) << "\n"
            << "      max allocation: " << mib(d.maxAlloc) << "\n";
    }
}

std::string clErrorName(cl_int code) {
    switch (code) {
#define PCL_CL_ERROR(name) \
    case name: return #name;
        PCL_CL_ERROR(CL_SUCCESS)
        PCL_CL_ERROR(CL_DEVICE_NOT_FOUND)
        PCL_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
        PCL_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
        PCL_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        PCL_CL_ERROR(CL_OUT_OF_RESOURCES)
        PCL_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
        PCL_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
        PCL_CL_ERROR(CL_MEM_COPY_OVERLAP)
        PCL_CL_ERROR(CL_IMAGE_FORMAT_MISMATCH)
        PCL_CL_ERROR(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        PCL_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
        PCL_CL_ERROR(CL_MAP_FAILURE)
        PCL_CL_ERROR(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        PCL_CL_ERROR(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        PCL_CL_ERROR(CL_COMPILE_PROGRAM_FAILURE)
        PCL_CL_ERROR(CL_LINKER_NOT_AVAILABLE)
        PCL_CL_ERROR(CL_LINK_PROGRAM_FAILURE)
        PCL_CL_ERROR(CL_DEVICE_PARTITION_FAILED)
        PCL_CL_ERROR(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        PCL_CL_ERROR(CL_INVALID_VALUE)
        PCL_CL_ERROR(CL_INVALID_DEVICE_TYPE)
        PCL_CL_ERROR(CL_INVALID_PLATFORM)
        PCL_CL_ERROR(CL_INVALID_DEVICE)
        PCL_CL_ERROR(CL_INVALID_CONTEXT)
        PCL_CL_ERROR(CL_INVALID_QUEUE_PROPERTIES)
        PCL_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
        PCL_CL_ERROR(CL_INVALID_HOST_PTR)
        PCL_CL_ERROR(CL_INVALID_MEM_OBJECT)
        PCL_CL_ERROR(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        PCL_CL_ERROR(CL_INVALID_IMAGE_SIZE)
        PCL_CL_ERROR(CL_INVALID_SAMPLER)
        PCL_CL_ERROR(CL_INVALID_BINARY)
        PCL_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
        PCL_CL_ERROR(CL_INVALID_PROGRAM)
        PCL_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
        PCL_CL_ERROR(CL_INVALID_KERNEL_NAME)
        PCL_CL_ERROR(CL_INVALID_KERNEL_DEFINITION)
        PCL_CL_ERROR(CL_INVALID_KERNEL)
        PCL_CL_ERROR(CL_INVALID_ARG_INDEX)
        PCL_CL_ERROR(CL_INVALID_ARG_VALUE)
        PCL_CL_ERROR(CL_INVALID_ARG_SIZE)
        PCL_CL_ERROR(CL_INVALID_KERNEL_ARGS)
        PCL_CL_ERROR(CL_INVALID_WORK_DIMENSION)
        PCL_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
        PCL_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
        PCL_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
        PCL_CL_ERROR(CL_INVALID_EVENT_WAIT_LIST)
        PCL_CL_ERROR(CL_INVALID_EVENT)
        PCL_CL_ERROR(CL_INVALID_OPERATION)
        PCL_CL_ERROR(CL_INVALID_GL_OBJECT)
        PCL_CL_ERROR(CL_INVALID_BUFFER_SIZE)
        PCL_CL_ERROR(CL_INVALID_MIP_LEVEL)
        PCL_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
        PCL_CL_ERROR(CL_INVALID_PROPERTY)
        PCL_CL_ERROR(CL_INVALID_IMAGE_DESCRIPTOR)
        PCL_CL_ERROR(CL_INVALID_COMPILER_OPTIONS)
        PCL_CL_ERROR(CL_INVALID_LINKER_OPTIONS)
        PCL_CL_ERROR(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef PCL_CL_ERROR
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "CL_UNKNOWN_ERROR";
    }
}

std::string formatMiB(size_t bytes) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
    return buf;
}

std::string describeMaxAlloc(const DeviceInfo& info) {
    const bool capped = info.bufferCap && info.bufferCap <= info.driverMaxAlloc;
    return formatMiB(info.maxAlloc) +
           (capped ? " (cap from --max-buffer-mib)" : " (the driver's CL_DEVICE_MAX_MEM_ALLOC_SIZE)");
}

DeviceError deviceError(const std::string& stage, const cl::Error& e) {
    std::ostringstream s;
    s << "stage " << stage << ": " << clErrorName(e.err()) << " (" << e.err() << ")";
    if (e.what() && std::string(e.what()) != "empty") s << " in " << e.what();
    return DeviceError(s.str());
}

// The memo of built programs. A mutex because the pipeline may ask from several host threads.
struct Device::Programs {
    std::mutex mutex;
    std::unique_ptr<ProgramCache> cache;
    std::map<std::pair<std::string, std::string>, cl::Program> built;
};

Device Device::open(const std::string& spec) {
    std::vector<DeviceInfo> devices = listDevices();
    const std::string want = lower(spec.empty() ? std::string("auto") : spec);
    const DeviceInfo* chosen = nullptr;
    auto firstOfType = [&](cl_device_type t) -> const DeviceInfo* {
        for (const DeviceInfo& d : devices)
            if (d.type & t) return &d;
        return nullptr;
    };
    if (want == "auto") {
        chosen = firstOfType(CL_DEVICE_TYPE_GPU);
        if (!chosen) chosen = firstOfType(CL_DEVICE_TYPE_CPU);
        if (!chosen && !devices.empty()) chosen = &devices.front();
    } else if (want == "gpu") {
        chosen = firstOfType(CL_DEVICE_TYPE_GPU);
    } else if (want == "cpu") {
        chosen = firstOfType(CL_DEVICE_TYPE_CPU);
    } else if (std::all_of(want.begin(), want.end(), [](unsigned char c) { return std::isdigit(c); })) {
        size_t index = want.size() > 9 ? devices.size() : std::stoul(want);
        if (index < devices.size()) chosen = &devices[index];
    } else {
        for (const DeviceInfo& d : devices)
            if (lower(d.name).find(want) != std::string::npos || lower(d.platform).find(want) != std::string::npos) {
                chosen = &d;
                break;
            }
    }
    if (!chosen) throw DeviceError("--device " + spec + ": no such OpenCL device; " + summary(devices));

    Device dev;
    dev.info_ = *chosen;
    guard("open " + chosen->name, [&] {
        dev.context_ = cl::Context(dev.info_.clDevice);
        dev.queue_ = cl::CommandQueue(dev.context_, dev.info_.clDevice, CL_QUEUE_PROFILING_ENABLE);
    });
    dev.programs_ = std::make_shared<Programs>();
    dev.programs_->cache = std::make_unique<ProgramCache>(dev.context_, dev.info_);
    // Idle buffers kept for reuse: at most an eighth of the device's memory, 2 GiB.
    dev.pool_ = std::make_shared<BufferPool>(std::min<size_t>(dev.info_.globalMem / 8, size_t(2) << 30));
    return dev;
}

cl::Program Device::program(const std::string& stage, const std::string& options) {
    std::lock_guard<std::mutex> lock(programs_->mutex);
    auto key = std::make_pair(stage, options);
    auto it = programs_->built.find(key);
    if (it != programs_->built.end()) return it->second;
    cl::Program p = programs_->cache->build(stage, options);
    programs_->built.emplace(key, p);
    return p;
}

void Device::setBufferCap(size_t bytes) {
    info_.bufferCap = bytes;
    info_.maxAlloc = bytes ? std::min(bytes, info_.driverMaxAlloc) : info_.driverMaxAlloc;
}

void Device::throwTooLarge(const std::string& what, size_t count, size_t elementBytes) const {
    throw DeviceError((what.empty() ? std::string("allocate: a buffer") : what) + " of " + std::to_string(count) +
                      " elements of " + std::to_string(elementBytes) + " bytes overflows size_t");
}

cl::Buffer Device::allocateBytes(size_t bytes, cl_mem_flags flags, const std::string& what) {
    bytes = std::max<size_t>(bytes, 1);
    if (observer_) observer_(what, bytes);
    if (bytes > info_.maxAlloc)
        throw DeviceError((what.empty() ? std::string("allocate: a buffer") : what) + " needs " + formatMiB(bytes) +
                          " (" + std::to_string(bytes) + " bytes), above the device's max allocation " +
                          describeMaxAlloc(info_));
    const std::string stage = what.empty() ? std::string("allocate") : what;
    if (!pool_) return guard(stage, [&] { return cl::Buffer(context_, flags, bytes); });
    cl::Buffer reused = guard(stage, [&] { return pool_->take(bytes, flags); });
    if (reused()) return reused;
    const size_t sized = BufferPool::sizeClass(bytes, info_.maxAlloc);
    cl::Buffer made = guard(stage, [&] { return cl::Buffer(context_, flags, sized); });
    guard(stage, [&] { pool_->keep(made, sized, flags); });
    return made;
}

double Device::elapsedSeconds(const cl::Event& e) {
    if (!e()) return 0.0;
    return guard("profiling", [&] {
        cl_ulong start = e.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        cl_ulong end = e.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        return double(end - start) * 1e-9;
    });
}

void Device::record(const cl::Kernel& k, const cl::Event& e) {
    profile_->launches.emplace_back(guard("profiling", [&] { return k.getInfo<CL_KERNEL_FUNCTION_NAME>(); }), e);
}

std::vector<Device::KernelTime> Device::kernelProfile() const {
    std::map<std::string, KernelTime> byName;
    if (profile_)
        for (const auto& [name, e] : profile_->launches) {
            KernelTime& t = byName[name];
            t.kernel = name;
            ++t.launches;
            guard("profiling", [&] { e.wait(); });
            t.seconds += elapsedSeconds(e);
        }
    std::vector<KernelTime> out;
    for (auto& [name, t] : byName) out.push_back(t);
    std::sort(out.begin(), out.end(), [](const KernelTime& a, const KernelTime& b) { return a.seconds > b.seconds; });
    return out;
}

}  // namespace pcl
