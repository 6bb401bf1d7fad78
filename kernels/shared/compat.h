/* compat.h: the common subset of C/C++ and OpenCL C that every shared header is written in.
 * __OPENCL_VERSION__ is predefined by every OpenCL C compiler, so one header serves both sides:
 * address-space qualifiers vanish on the host, functions become static inline, and the
 * fixed-width integer names are the same everywhere. */
#ifndef PCL_COMPAT_H
#define PCL_COMPAT_H

#ifdef __OPENCL_VERSION__
  #define PCL_DEVICE 1
  #define PCL_INLINE inline
  #define PCL_GLOBAL __global
  #define PCL_CONSTANT __constant
  #define PCL_PRIVATE __private
  typedef uint  pcl_u32;
  typedef int   pcl_i32;
  typedef ulong pcl_u64;
  typedef float pcl_f32;
  /* OpenCL C has no static_assert before 2.0: a negative array size fails the build instead. */
  #define PCL_STATIC_ASSERT(cond, name) typedef char pcl_static_assert_##name[(cond) ? 1 : -1]
#else
  #include <stdint.h>
  #include <math.h>
  #define PCL_DEVICE 0
  #define PCL_INLINE static inline
  #define PCL_GLOBAL
  #define PCL_CONSTANT
  #define PCL_PRIVATE
  typedef uint32_t pcl_u32;
  typedef int32_t  pcl_i32;
  typedef uint64_t pcl_u64;
  typedef float    pcl_f32;
  #ifdef __cplusplus
    #define PCL_STATIC_ASSERT(cond, name) static_assert(cond, #name)
  #else
    #define PCL_STATIC_ASSERT(cond, name) _Static_assert(cond, #name)
  #endif
#endif

#endif /* PCL_COMPAT_H */
