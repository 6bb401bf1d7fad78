// Kernel sources compiled into the binary by scripts/embed_kernels.py, so photoncl runs from
// any directory. PHOTONCL_KERNEL_DIR (see program_cache.h) reads them from disk instead.
#pragma once

namespace pcl {

struct EmbeddedKernel {
    const char* name;    // stage name: kernels/<name>.cl
    const char* source;  // includes expanded, #line markers kept
};

// Terminated by {nullptr, nullptr}.
extern const EmbeddedKernel kEmbeddedKernels[];

}  // namespace pcl
