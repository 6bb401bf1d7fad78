// Device: one OpenCL device with its context, a profiling command queue, the programs built for
// it (through ProgramCache, memoised per (stage, options)) and typed buffer helpers.
//
// Every OpenCL call that can fail goes through guard()/launch(), which turn a cl::Error into a
// DeviceError naming the stage ("stage trace: CL_OUT_OF_RESOURCES (-5) in clEnqueueNDRangeKernel"),
// so a failure says which step of the pipeline it came from. Typical use:
//
//   pcl::Device dev = pcl::Device::open("auto");
//   auto trace = dev.kernel<cl::Buffer, cl::Buffer, cl_uint>("trace", "trace_closest");
//   cl::Buffer rays = dev.upload(hostRays);
//   cl::Buffer hits = dev.allocate<PclHit>(n);
//   dev.launch("trace", trace, cl::NDRange(n), rays, hits, cl_uint(n));
//   std::vector<PclHit> out = dev.download<PclHit>(hits, n);
#pragma once

#include <CL/opencl.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace pcl {

class BufferPool;
class ProgramCache;

struct DeviceInfo {
    int index = -1;        // position in listDevices(): platforms in order, devices in order
    std::string platform;  // platform name
    std::string platformVersion;
    std::string name, vendor, version, driver;
    cl_device_type type = 0;  // CL_DEVICE_TYPE_CPU / _GPU / _ACCELERATOR
    size_t computeUnits = 0;
    size_t globalMem = 0;       // bytes
    size_t maxAlloc = 0;        // bytes: the largest single buffer this Device allocates: the
                                // driver's, or the buffer cap when that is lower (Device::setBufferCap)
    size_t driverMaxAlloc = 0;  // bytes: CL_DEVICE_MAX_MEM_ALLOC_SIZE as the driver reports it
    size_t bufferCap = 0;       // bytes: the cap from setBufferCap (--max-buffer-mib); 0: none
    // CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT in CL_DEVICE_SINGLE_FP_CONFIG: the device can divide and
    // take square roots correctly rounded, as the CPU twins do (ProgramCache asks it to).
    bool correctlyRoundedDivideSqrt = false;
    cl::Platform clPlatform;
    cl::Device clDevice;
};

// Every device of every platform. An absent ICD loader or zero platforms gives an empty list.
std::vector<DeviceInfo> listDevices();

// `photoncl devices`: one block per device with index, type, compute units, memory, max
// allocation and driver; says so when there is none.
void printDevices(std::ostream& out);

// "CPU", "GPU", "accelerator", ...
std::string deviceTypeName(cl_device_type type);

// "CL_OUT_OF_RESOURCES" for -5; "CL_UNKNOWN_ERROR" for codes it does not know.
std::string clErrorName(cl_int code);

// "64.0 MiB": bytes in MiB with one decimal (memory messages and the memory plan's table).
std::string formatMiB(size_t bytes);

// The max allocation and where it comes from, for messages: "64.0 MiB (cap from
// --max-buffer-mib)" or "6016.0 MiB (the driver's CL_DEVICE_MAX_MEM_ALLOC_SIZE)".
std::string describeMaxAlloc(const DeviceInfo& info);

// The DeviceError for a failed OpenCL call during `stage`.
DeviceError deviceError(const std::string& stage, const cl::Error& e);

class Device {
public:
    // spec: "auto" (a GPU if there is one, else a CPU, else anything), "cpu", "gpu", a device
    // index from listDevices(), or a case-insensitive substring of the device or platform name.
    // No match throws DeviceError listing the devices there are. ("ref" is the CLI's business.)
    static Device open(const std::string& spec = "auto");

    const DeviceInfo& info() const { return info_; }
    cl::Context& context() { return context_; }
    cl::Device& device() { return info_.clDevice; }
    cl::CommandQueue& queue() { return queue_; }

    // The built program kernels/<stage>.cl with extra build options (e.g. "-DPCL_ANY_HIT=1"),
    // from the on-disk binary cache when possible. Built once per (stage, options) per Device
    // (copies of a Device share the memo). Build failures throw DeviceError with the kernel
    // file, the device, the options and the compiler's log.
    cl::Program program(const std::string& stage, const std::string& options = "");

    // A typed kernel entry point of program(stage, options).
    template <class... Ts>
    cl::KernelFunctor<Ts...> kernel(const std::string& stage, const std::string& entry,
                                    const std::string& options = "") {
        cl::Program p = program(stage, options);
        return guard(stage, [&] { return cl::KernelFunctor<Ts...>(p, entry); });
    }

    // Runs f(); a cl::Error thrown inside becomes DeviceError("stage <stage>: ...").
    template <class F>
    static auto guard(const std::string& stage, F&& f) -> decltype(f()) {
        try {
            return f();
        } catch (const cl::Error& e) {
            throw deviceError(stage, e);
        }
    }

    // Enqueues k over `global` work-items (local size chosen by the runtime) and returns its
    // event. A zero-sized launch is skipped (OpenCL rejects it) and returns an empty event.
    template <class... Ts, class... Args>
    cl::Event launch(const std::string& stage, cl::KernelFunctor<Ts...>& k, const cl::NDRange& global, Args&&... args) {
        if (isEmpty(global)) return cl::Event();
        cl::Event e = guard(stage, [&] { return k(cl::EnqueueArgs(queue_, global), std::forward<Args>(args)...); });
        if (profile_) record(k.getKernel(), e);
        return e;
    }
    // The same with an explicit work-group size (a separate name: an NDRange argument would
    // otherwise be taken for a kernel argument by the overload above).
    template <class... Ts, class... Args>
    cl::Event launchLocal(const std::string& stage, cl::KernelFunctor<Ts...>& k, const cl::NDRange& global,
                          const cl::NDRange& local, Args&&... args) {
        if (isEmpty(global)) return cl::Event();
        cl::Event e =
            guard(stage, [&] { return k(cl::EnqueueArgs(queue_, global, local), std::forward<Args>(args)...); });
        if (profile_) record(k.getKernel(), e);
        return e;
    }

    // Launch profile: while on, every launch's event is kept; kernelProfile() waits for them and
    // gives device seconds and launch counts per kernel name, largest first (render --profile).
    struct KernelTime {
        std::string kernel;
        size_t launches = 0;
        double seconds = 0.0;
    };
    void setProfiling(bool on) { profile_ = on ? std::make_shared<Profile>() : nullptr; }
    std::vector<KernelTime> kernelProfile() const;

    // Caps every buffer this Device allocates at `bytes` (0: no cap). info().maxAlloc becomes
    // min(driver's, bytes), so every stage that sizes its batches from it splits its work under
    // the cap, and allocateBytes() refuses anything larger. The cap belongs to this copy: a copy
    // of the tests' shared Device can be capped without touching the others.
    void setBufferCap(size_t bytes);

    // Told (what, bytes) before each buffer is created: tests compare the memory plan
    // (pipeline/memory_plan.h) with what the stages really allocate. Empty: none.
    using AllocationObserver = std::function<void(const std::string& what, size_t bytes)>;
    void setAllocationObserver(AllocationObserver observer) { observer_ = std::move(observer); }

    // The one way a buffer is made: `what` names it in errors ("photon pass: slots"). Large
    // buffers come from the device's BufferPool when one of their size is free. A buffer
    // above info().maxAlloc throws DeviceError "<what> needs N MiB, above the device's max
    // allocation M MiB (cap from --max-buffer-mib)" instead of failing later, or silently, in
    // the driver. Zero bytes become one element's worth (OpenCL refuses empty buffers).
    cl::Buffer allocateBytes(size_t bytes, cl_mem_flags flags, const std::string& what);

    // Buffers hold at least one element: OpenCL refuses zero-sized buffers, and an empty scene
    // part (no spheres, say) still needs a valid kernel argument.
    template <class T>
    cl::Buffer allocate(size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE, const std::string& what = {}) {
        if (count > SIZE_MAX / sizeof(T)) throwTooLarge(what, count, sizeof(T));
        return allocateBytes(std::max<size_t>(count, 1) * sizeof(T), flags, what);
    }
    // A buffer holding a copy of `data` (blocking write, so `data` may go away after the call).
    template <class T>
    cl::Buffer upload(const std::vector<T>& data, cl_mem_flags flags = CL_MEM_READ_ONLY, const std::string& what = {}) {
        cl::Buffer buf = allocate<T>(data.size(), flags, what);
        if (!data.empty())
            guard("upload", [&] { queue_.enqueueWriteBuffer(buf, CL_TRUE, 0, data.size() * sizeof(T), data.data()); });
        return buf;
    }
    // The first `count` elements of `buf` (blocking read: waits for the kernels writing it).
    template <class T>
    std::vector<T> download(const cl::Buffer& buf, size_t count) {
        std::vector<T> out;
        downloadInto(buf, count, out);
        return out;
    }
    // The same into `out` (resized to count): a caller that downloads every chunk keeps one vector
    // and its pages instead of faulting in fresh ones each time.
    template <class T>
    void downloadInto(const cl::Buffer& buf, size_t count, std::vector<T>& out) {
        out.resize(count);
        if (count) guard("download", [&] { queue_.enqueueReadBuffer(buf, CL_TRUE, 0, count * sizeof(T), out.data()); });
    }
    // Fills `count` elements of `buf` with `value`.
    template <class T>
    void fill(cl::Buffer& buf, const T& value, size_t count) {
        if (count) guard("fill", [&] { queue_.enqueueFillBuffer(buf, value, 0, count * sizeof(T)); });
    }

    void finish() {
        guard("finish", [&] { queue_.finish(); });
    }

    // Seconds between an event's start and end (the queue has profiling enabled).
    static double elapsedSeconds(const cl::Event& e);

private:
    Device() = default;
    static bool isEmpty(const cl::NDRange& r) {
        for (size_t i = 0; i < r.dimensions(); ++i)
            if (r.get()[i] == 0) return true;
        return r.dimensions() == 0;
    }

    [[noreturn]] void throwTooLarge(const std::string& what, size_t count, size_t elementBytes) const;

    struct Profile {
        std::vector<std::pair<std::string, cl::Event>> launches;
    };
    void record(const cl::Kernel& k, const cl::Event& e);

    struct Programs;  // the memo and the ProgramCache, shared by copies
    DeviceInfo info_;
    AllocationObserver observer_;
    cl::Context context_;
    cl::CommandQueue queue_;
    std::shared_ptr<Programs> programs_;
    std::shared_ptr<Profile> profile_;
    std::shared_ptr<BufferPool> pool_;  // large buffers for reuse (device/buffer_pool.h), shared by copies
};

}  // namespace pcl
