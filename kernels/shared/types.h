/* types.h: the only definition of every buffer struct that crosses the host/device boundary.
 * Scalars only (a float3 is 16 bytes on the device and 12 on the host), padding spelled out,
 * and a size assert per struct on both sides. kernels/probe.cl reports the device-side sizes
 * so a test can compare them with sizeof on the host. */
#ifndef PCL_TYPES_H
#define PCL_TYPES_H

#include "compat.h"

/* ---- Rays and hits (traversal kernel I/O) ---------------------------------------------- */

typedef struct PclRay {
    pcl_f32 ox, oy, oz, tmin;
    pcl_f32 dx, dy, dz, tmax;
    pcl_f32 time;  /* normalised shutter time in [0,1]: moving primitives sit at p + motion*time */
    pcl_u32 pad0, pad1, pad2;
} PclRay;
PCL_STATIC_ASSERT(sizeof(PclRay) == 48, PclRay_size);

#define PCL_NO_HIT 0xFFFFFFFFu

typedef struct PclHit {
    pcl_f32 t, u, v;  /* distance along the (unnormalised) direction; barycentrics for triangles */
    pcl_u32 prim;     /* global primitive id (triangles first, then spheres) or PCL_NO_HIT */
} PclHit;
PCL_STATIC_ASSERT(sizeof(PclHit) == 16, PclHit_size);

/* ---- Wide BVH ----------------------------------------------------------------------------
 * Eight-way nodes whose child boxes are stored as structure-of-arrays, so a kernel loads each
 * coordinate with one vload8 and tests all eight boxes at once (PoCL does not vectorise a
 * traversal loop across work-items, but compiles explicit vector types well: shared/bvh.h).
 * Node 0 is the root.
 *
 * Child word encoding:
 *   PCL_CHILD_EMPTY           unused slot
 *   bit 31 clear              interior node index
 *   bit 31 set                leaf; bit 30 set: sphere leaf, clear: triangle-packet leaf;
 *                             bits 26..29: item count - 1 (1..16 items);
 *                             bits 0..25: first item (PclTriPacket or PclSphere index). */
#define PCL_BVH_WIDTH 8
#define PCL_CHILD_EMPTY 0xFFFFFFFFu
#define PCL_CHILD_LEAF 0x80000000u
#define PCL_CHILD_SPHERES 0x40000000u
#define PCL_CHILD_COUNT_SHIFT 26
#define PCL_CHILD_COUNT_MASK 0xFu
#define PCL_CHILD_INDEX_MASK 0x03FFFFFFu

typedef struct PclBvhNode {
    pcl_f32 lox[8], loy[8], loz[8];
    pcl_f32 hix[8], hiy[8], hiz[8];
    pcl_u32 child[8];
} PclBvhNode;
PCL_STATIC_ASSERT(sizeof(PclBvhNode) == 224, PclBvhNode_size);

/* Four triangles tested together (Möller–Trumbore with float4). Empty lanes have prim ==
 * PCL_NO_HIT and degenerate edges. All lanes of a packet share one motion translation. */
typedef struct PclTriPacket {
    pcl_f32 v0x[4], v0y[4], v0z[4];
    pcl_f32 e1x[4], e1y[4], e1z[4];
    pcl_f32 e2x[4], e2y[4], e2z[4];
    pcl_u32 prim[4];
    pcl_f32 mx, my, mz;  /* translation over the shutter interval (0 for static geometry) */
    pcl_u32 pad0;
} PclTriPacket;
PCL_STATIC_ASSERT(sizeof(PclTriPacket) == 176, PclTriPacket_size);

typedef struct PclSphere {
    pcl_f32 cx, cy, cz, radius;
    pcl_f32 mx, my, mz;  /* translation over the shutter interval */
    pcl_u32 prim;        /* global primitive id */
} PclSphere;
PCL_STATIC_ASSERT(sizeof(PclSphere) == 32, PclSphere_size);


/* ---- Scene shading data (photon pass, camera pass) -------------------------------------- */

#define PCL_SPECULAR_NONE 0u
#define PCL_SPECULAR_MIRROR 1u
#define PCL_SPECULAR_GLOSSY 2u
#define PCL_SPECULAR_DIELECTRIC 3u

#define PCL_MATERIAL_INTERFACE 1u /* an invisible medium boundary: paths pass straight through */
typedef struct PclMaterial {
    pcl_f32 rhoD[4];      /* diffuse reflectance rgb, [3] = 0 */
    pcl_f32 rhoS[4];      /* specular reflectance rgb, [3] = 0 */
    pcl_f32 emission[4];  /* one-sided emitted radiance rgb, [3] = 0 */
    pcl_u32 specular;     /* PCL_SPECULAR_* */
    pcl_f32 exponent;     /* glossy: normalised Phong exponent */
    pcl_f32 ior;          /* dielectric: index inside (outside 1) */
    pcl_u32 flags;        /* PCL_MATERIAL_*; 0 for an ordinary surface */
} PclMaterial;
PCL_STATIC_ASSERT(sizeof(PclMaterial) == 64, PclMaterial_size);

/* Indexed by global primitive id (triangles first, then spheres; see SceneGeometry). */
typedef struct PclPrimInfo {
    pcl_f32 a, b, c;   /* triangle: unit geometric normal; sphere: centre at shutter time 0 */
    pcl_u32 material;  /* index into the PclMaterial array */
    pcl_f32 mx, my, mz;/* translation over the shutter interval */
    pcl_f32 radius;    /* sphere radius; 0 for triangles */
} PclPrimInfo;
PCL_STATIC_ASSERT(sizeof(PclPrimInfo) == 32, PclPrimInfo_size);

/* ---- Participating media (homogeneous; prep/medium_boundaries decides the sides) -------- */

#define PCL_NO_MEDIUM -1 /* vacuum */
/* lightMedia of a directional light in a global medium: its light crosses infinitely much of it
 * and arrives with nothing (as the reference path tracer's shadow rays find); the path ends at
 * once, ABSORBED, with no record. */
#define PCL_MEDIUM_UNREACHABLE -2
typedef struct PclMedium {
    pcl_f32 sigmaA[4];  /* absorption rgb in 1/m, [3] = 0 */
    pcl_f32 sigmaS[4];  /* scattering rgb in 1/m, [3] = 0 */
    pcl_f32 g;          /* Henyey-Greenstein asymmetry, |g| < 1 */
    pcl_f32 pad0, pad1, pad2;
} PclMedium;
PCL_STATIC_ASSERT(sizeof(PclMedium) == 48, PclMedium_size);

/* Per global primitive: the medium on either side (PclMedium index or PCL_NO_MEDIUM). A path
 * leaving the primitive against its geometric normal (d.n < 0) is in `inside`, else `outside`. */
typedef struct PclPrimMedium {
    pcl_i32 inside, outside;
} PclPrimMedium;
PCL_STATIC_ASSERT(sizeof(PclPrimMedium) == 8, PclPrimMedium_size);

/* ---- Lights: one entry per point/spot/directional light and per emitting triangle -------- */

#define PCL_LIGHT_POINT 0u
#define PCL_LIGHT_SPOT 1u
#define PCL_LIGHT_TRIANGLE 2u
#define PCL_LIGHT_DIRECTIONAL 3u
#define PCL_LIGHT_ENVIRONMENT 4u /* the sky: p, radius = the scene's bounding sphere (photons only; shared/environment.h) */

typedef struct PclLight {
    pcl_u32 type;       /* PCL_LIGHT_* */
    pcl_u32 prim;       /* triangle: global primitive id; others PCL_NO_HIT */
    pcl_u32 projFirst;  /* projection map: first marked cell in the cell array */
    pcl_u32 projCount;  /* projection map: marked cells (of PCL_PROJ_GRID^2); 0: no caustics */
    pcl_f32 p[4];       /* point/spot: position; triangle: vertex p0; directional: disc centre */
    pcl_f32 e1[4];      /* triangle: p1 - p0; sky: the ball its caustic photons aim at (centre, [3] radius; 0: none) */
    pcl_f32 e2[4];      /* triangle: p2 - p0 */
    pcl_f32 axis[4];    /* spot: cone axis; directional: travel direction; triangle: unit normal of the emitting side */
    pcl_f32 power[4];   /* flux rgb in W emitted by this entry */
    pcl_f32 motion[4];  /* triangle: translation over the shutter interval */
    pcl_f32 cosInner, cosOuter;  /* spot */
    pcl_f32 radius;     /* directional: radius of the disc covering the scene */
    pcl_f32 area;       /* triangle: area */
} PclLight;
PCL_STATIC_ASSERT(sizeof(PclLight) == 128, PclLight_size);

/* Projection maps (Jensen 1996): a PCL_PROJ_GRID x PCL_PROJ_GRID grid over the unit square of
 * a light's direction sample (position sample for directional lights); a cell is marked when
 * some sample in it can send a photon towards a specular object. */
#define PCL_PROJ_GRID 32u

/* ---- Photon pass ---------------------------------------------------------------------- */

/* A photon leaving its light (emit → trace_photons). */
typedef struct PclPhotonRay {
    pcl_f32 ox, oy, oz, time;  /* origin; normalised shutter time */
    pcl_f32 dx, dy, dz;        /* unit direction */
    pcl_u32 light;             /* PclLight index */
    pcl_f32 power[4];          /* flux rgb in W, [3] = 0 */
} PclPhotonRay;
PCL_STATIC_ASSERT(sizeof(PclPhotonRay) == 48, PclPhotonRay_size);

/* A stored photon, 24 bytes: Jensen's 20 (position, power in Ward's RGBE, incoming direction
 * compressed to (theta, phi) bytes, flags) plus the surface normal on the side the photon
 * arrived from, octahedral-encoded in two 16-bit snorms: the radiance estimate rejects photons
 * whose surface faces another way (n_p·n_q < 0.9), which stops light leaking through thin
 * walls and round corners (kernels/README.md, "estimate"). */
#define PCL_PHOTON_THETA_SHIFT 0
#define PCL_PHOTON_PHI_SHIFT 8
#define PCL_PHOTON_BOUNCE_SHIFT 16      /* bounces before this hit (0: straight from the light) */
#define PCL_PHOTON_CAUSTIC 0x01000000u  /* stored in the caustic map */
#define PCL_PHOTON_AFTER_SPECULAR 0x02000000u /* the path had a specular bounce */
#define PCL_PHOTON_AFTER_DIFFUSE 0x04000000u  /* the path had a diffuse bounce (or a medium scattering event) */
#define PCL_PHOTON_VOLUME 0x20000000u         /* a volume photon: stored at a scattering event in a medium;
                                                  its rgbe is the power scattered there (Φ σs Tr/p), its
                                                  normal 0 (kernels/trace_photons.cl, media) */
typedef struct PclPhoton {
    pcl_f32 x, y, z;
    pcl_u32 rgbe;     /* r | g << 8 | b << 16 | e << 24 */
    pcl_u32 packed;   /* theta | phi << 8 | bounce << 16 | flags */
    pcl_u32 normal;   /* octahedral u | v << 16, snorm16 each (photon_normal_encode) */
} PclPhoton;
PCL_STATIC_ASSERT(sizeof(PclPhoton) == 24, PclPhoton_size);

/* How a photon path ended (trace_photons output, one per path): bits 0..7 bounces traced,
 * bits 8..11 the cause. */
#define PCL_END_ESCAPED 1u    /* left the scene */
#define PCL_END_ABSORBED 2u   /* Russian roulette absorbed it (or a glossy sample went below the surface) */
#define PCL_END_MAX_DEPTH 3u  /* reached maxDepth bounces */
#define PCL_END_STORED 4u     /* caustic pass: ended (diffuse lobe or absorbed) at a hit it deposited at */

/* Media: a photon path crosses at most this many invisible medium boundaries within one bounce
 * (it ends with PCL_END_MAX_DEPTH past them); each crossing starts a new random-number block. */
#define PCL_MAX_SEGMENTS 64u

#define PCL_PASS_GLOBAL 0u
#define PCL_PASS_CAUSTIC 1u

typedef struct PclPhotonParams {
    pcl_u32 seedLo, seedHi;  /* the pass seed (render seed mixed with the pass index) */
    pcl_u32 firstPhoton;     /* photon index of this batch's first path */
    pcl_u32 batchSize;       /* paths in this batch */
    pcl_u32 lightCount;
    pcl_u32 triangleCount;   /* global ids at or above it are spheres */
    pcl_u32 maxDepth;        /* bounces; also the deposit slots per path (either pass) */
    pcl_u32 pass;            /* PCL_PASS_GLOBAL or PCL_PASS_CAUSTIC */
    pcl_u32 hasMotion;       /* 0: every photon at time 0 (no time sampling) */
    pcl_u32 storeGlobal;     /* global pass: deposit into the global map */
    pcl_f32 rayEpsilon;      /* spawn offset along the normal, scaled to the scene */
    pcl_u32 hasMedia;        /* 0: no medium anywhere (the media buffers are placeholders) */
} PclPhotonParams;
PCL_STATIC_ASSERT(sizeof(PclPhotonParams) == 48, PclPhotonParams_size);

/* ---- Photon maps: balanced kd-tree, hash grid, k nearest neighbours ---------------------
 * kd-tree: Jensen's left-balanced tree stored implicitly as a heap over the photon array
 * itself (node i has children 2i+1 and 2i+2; no pointers). The split axis of node i (0 x,
 * 1 y, 2 z) is in bits 27..28 of its photon's `packed` word. kernels/README.md, "Photon maps". */
#define PCL_PHOTON_AXIS_SHIFT 27
#define PCL_PHOTON_AXIS_MASK 0x18000000u

/* Hash grid (as SmallVCM's): photons sorted by hashed cell; cellStart/cellEnd per table entry. */
typedef struct PclGridParams {
    pcl_f32 ox, oy, oz;   /* grid origin: the map's bounds minimum */
    pcl_f32 cellSize;     /* tied to the search radius: 2 r_max, so a query reads 2x2x2 cells */
    pcl_f32 invCellSize;
    pcl_u32 tableSize;    /* hashed cells (a power of two) */
    pcl_u32 photonCount;
    pcl_u32 pad0;
} PclGridParams;
PCL_STATIC_ASSERT(sizeof(PclGridParams) == 32, PclGridParams_size);

/* One k-nearest-neighbour query: the k photons nearest (x, y, z) within sqrt(maxRadius2). */
typedef struct PclKnnQuery {
    pcl_f32 x, y, z, maxRadius2;
    pcl_u32 k;            /* 1 .. PCL_KNN_MAX_K */
    pcl_u32 pad0, pad1, pad2;
} PclKnnQuery;
PCL_STATIC_ASSERT(sizeof(PclKnnQuery) == 32, PclKnnQuery_size);
#define PCL_KNN_MAX_K 500u

/* ---- Radiance estimate (kernels/estimate.cl; kernels/README.md, "estimate") ---------------- */

/* One irradiance estimate: at (x, y, z) on the side of unit normal (nx, ny, nz), from the k
 * photons nearest within sqrt(maxRadius2). The first four floats are PclKnnQuery's. */
typedef struct PclEstimateQuery {
    pcl_f32 x, y, z, maxRadius2;
    pcl_f32 nx, ny, nz;
    pcl_u32 k;            /* 1 .. PCL_KNN_MAX_K, or'ed with PCL_QUERY_NONDIRECT */
} PclEstimateQuery;
PCL_STATIC_ASSERT(sizeof(PclEstimateQuery) == 32, PclEstimateQuery_size);
/* In PclEstimateQuery.k: the estimate (and the precomputed lookup) answers with the irradiance of
 * the photons that did not come straight from a light (bounce > 0): final_gather's short gather
 * rays add the direct part by shadow rays instead. The k nearest are searched as without it. */
#define PCL_QUERY_NONDIRECT 0x80000000u
#define PCL_QUERY_K_MASK 0x0000FFFFu

#define PCL_FILTER_BOX 0u
#define PCL_FILTER_CONE 1u
#define PCL_FILTER_EPANECHNIKOV 2u
#define PCL_FILTER_GAUSSIAN 3u
#define PCL_GAUSSIAN_BETA 1.953f  /* Jensen 2001, §7.2.2 (Pavicic's Gaussian) */

/* One estimate launch (a batch of queries). */
typedef struct PclEstimateParams {
    pcl_u32 filter;        /* PCL_FILTER_* */
    pcl_f32 coneK;         /* cone: k_c >= 1 */
    pcl_f32 norm;          /* the filter's normalisation: mean of w over the unit disc (float) */
    pcl_f32 gaussianScale; /* Gaussian: 1 / (1 - e^-beta) (float) */
    pcl_f32 minNormalCos;  /* a photon counts when n_p . n_q >= this */
    pcl_u32 visibility;    /* 1: reject photons whose lifted segment to the query is occluded */
    pcl_f32 rayEpsilon;    /* visibility: lift h = rayEpsilon + liftFraction * r */
    pcl_f32 liftFraction;  /* 0.25 */
    pcl_u32 firstQuery;    /* this batch's first query (queries and results are indexed from 0) */
    pcl_u32 queryCount;    /* queries in this batch */
    pcl_u32 stride;        /* kNN slots per query (the batch's largest k) */
    pcl_f32 maxSearchRadius2; /* the structure's own search limit (hash grid r_max^2, else +inf) */
} PclEstimateParams;
PCL_STATIC_ASSERT(sizeof(PclEstimateParams) == 48, PclEstimateParams_size);

/* The estimate at one query. */
typedef struct PclEstimate {
    pcl_f32 r, g, b;       /* irradiance E in W/m^2; exactly 0 when no photon counts */
    pcl_f32 radius2;       /* r^2: the kNN's squared distance to its last photon (0 if none) */
    pcl_u32 used;          /* photons that passed the rejection tests */
    pcl_u32 found;         /* photons the kNN returned */
    pcl_u32 nondirect;     /* RGBE (photon_rgbe_encode) of E over the photons of bounce > 0 alone,
                              the same disc and weights (PCL_QUERY_NONDIRECT) */
    pcl_u32 pad0;
} PclEstimate;
PCL_STATIC_ASSERT(sizeof(PclEstimate) == 32, PclEstimate_size);

/* ---- Precomputed irradiance (Christensen 1999; kernels/README.md, "precomputed irradiance") --
 * The irradiance estimated at every m-th photon of the global map, stored with the photon's
 * position and normal, so a later lookup is one nearest-neighbour search (with the normal test)
 * instead of a k-nearest-neighbour estimate. Floats, not RGBE: a lookup at a stored point's own
 * position returns exactly what was estimated there. Lookups take PclEstimateQuery (k unused),
 * so one query buffer serves the full estimate and the lookup. */
#define PCL_IRRADIANCE_AXIS_SHIFT 30
#define PCL_IRRADIANCE_INDEX_MASK 0x3FFFFFFFu
/* The lookup's buckets (precomputed_irradiance.cl, shared/kd_buckets.h): 9 rows of one float per
 * node: x, y, z, cover, normal x, y, z, photon index, heap node. */
#define PCL_IRRADIANCE_BUCKET_ROWS 9u
/* Floats after the last kd-tree bucket, so its 8-wide row loads stay inside the buffer. */
#define PCL_KD_BUCKET_PAD_FLOATS 8u
typedef struct PclIrradiancePoint {
    pcl_f32 x, y, z;
    pcl_u32 normal;   /* the photon's octahedral normal word (photon_normal_encode) */
    pcl_f32 r, g, b;  /* irradiance in W/m² */
    pcl_u32 photon;   /* map index of the photon it was estimated at (bits 0..29); in the lookup
                         tree, the node's split axis in bits 30..31 */
} PclIrradiancePoint;
PCL_STATIC_ASSERT(sizeof(PclIrradiancePoint) == 32, PclIrradiancePoint_size);

/* ---- Eye pass (camera.cl, eye_paths.cl, direct_light.cl, final_gather.cl, eye_estimate.cl;
 * kernels/README.md, "Eye pass") ------------------------------------------------------------
 * Sample s of a pass (s = pixel * n² + k, pixel = y * width + x, k in [0, n²)) is the k-th of
 * the pixel's n × n strata. Work-item i of a launch handles s = firstSample + i; every output
 * array is indexed by i. Random numbers: key = the pass seed, path = pixel, bounce = k (or a
 * per-stage function of k, see the README), stream per stage. */

typedef struct PclCameraParams {
    pcl_f32 position[4];      /* camera position (xyz) */
    pcl_f32 forward[4];       /* unit view direction */
    pcl_f32 right[4];         /* unit, forward × up */
    pcl_f32 up[4];            /* unit, right × forward */
    pcl_f32 tanHalfWidth, tanHalfHeight;
    pcl_f32 apertureRadius;   /* thin lens radius (used when lensSampling) */
    pcl_f32 focusDistance;    /* distance of the plane of focus along forward */
    pcl_u32 seedLo, seedHi;   /* the pass seed */
    pcl_u32 width, height;
    pcl_u32 strata;           /* n: n × n stratified samples per pixel per pass */
    pcl_u32 firstSample;      /* s of work-item 0 */
    pcl_u32 sampleCount;      /* samples in this launch */
    pcl_u32 lensSampling;     /* 0: pinhole (the plan: RenderPlan::lensSampling) */
    pcl_u32 timeSampling;     /* 0: time 0 (RenderPlan::timeSampling) */
    pcl_u32 pad0, pad1, pad2;
} PclCameraParams;
/* The bounce word of the Philox block (stream CAMERA, path = pixel) whose words shift the pixel's
 * copy of the pass's lens (0, 1) and time (2) patterns (stratify_shifted): above every k < n². */
#define PCL_CAMERA_PATTERN_BOUNCE 0xFFFFFFFFu
PCL_STATIC_ASSERT(sizeof(PclCameraParams) == 128, PclCameraParams_size);

typedef struct PclEyeParams {
    pcl_u32 seedLo, seedHi;   /* the pass seed (as the camera's) */
    pcl_u32 samplesPerPixel;  /* n² */
    pcl_u32 firstSample;      /* s of work-item 0 */
    pcl_u32 sampleCount;
    pcl_u32 triangleCount;    /* global ids at or above it are spheres */
    pcl_u32 maxDepth;         /* hits examined along the chain (specular bounces + 1), 1..64 */
    pcl_f32 rayEpsilon;       /* spawn offset along the normal */
    pcl_u32 lightCount;       /* lights[] entries (next-event estimation at glossy hits) */
    pcl_f32 areaPowerTotal;   /* Σ scalar power of the triangle lights (their choice density) */
    pcl_i32 cameraMedium;     /* media: the medium the camera rays start in (PCL_NO_MEDIUM: vacuum) */
    pcl_u32 volumeSegments;   /* media: PclVolumeSegment slots per record (≥ 1); 0 in a scene without
                                 media, whose media buffers are placeholders the kernel never reads */
    pcl_f32 sceneCentre[3];   /* the scene's bounding sphere (SceneBuffers): a segment that leaves the */
    pcl_f32 sceneRadius;      /* scene is recorded up to where the ray leaves it */
} PclEyeParams;
PCL_STATIC_ASSERT(sizeof(PclEyeParams) == 64, PclEyeParams_size);

/* One eye segment inside a scattering medium (eye_paths → volume_estimate): the in-scattered
 * radiance the eye receives along it is throughput × ∫_0^length Tr(t) σs ∫ p L dω dt. Stored
 * slot-major like the photon slots: segments[k * sampleCount + i] for k < segmentCounts[i], at
 * most PclEyeParams.volumeSegments per record. A segment lies in one medium (an invisible
 * boundary starts a new one) and is finite: a ray that leaves the scene ends at the scene's
 * bounding sphere, beyond which there are no photons. */
typedef struct PclVolumeSegment {
    pcl_f32 ox, oy, oz, length;  /* start and length along the unit direction */
    pcl_f32 dx, dy, dz, time;    /* unit direction of travel (away from the eye); shutter time */
    pcl_f32 throughput[4];       /* the eye path's weight at the start (transmittance before it included), rgb */
    pcl_i32 medium;              /* index into the medium table (PclMedium[]) */
    pcl_u32 record;              /* the eye record i of the chunk it belongs to */
    pcl_u32 pad0, pad1;
} PclVolumeSegment;
PCL_STATIC_ASSERT(sizeof(PclVolumeSegment) == 64, PclVolumeSegment_size);

#define PCL_EYE_DIFFUSE 1u   /* the record holds a diffuse hit (prim != PCL_NO_HIT) */
#define PCL_EYE_TRUNCATED 2u /* media: the chain ended early, its segment slots (volumeSegments) full or
                                PCL_MAX_SEGMENTS invisible boundaries crossed at one hit (never silently) */

/* One eye sample after its specular chain (eye_paths.cl). */
typedef struct PclEyeHit {
    pcl_f32 x, y, z, time;    /* the first hit whose diffuse part was chosen; shutter time */
    pcl_f32 nx, ny, nz;       /* unit geometric normal on the viewer's side of that surface */
    pcl_u32 prim;             /* its primitive, PCL_NO_HIT when the chain found no diffuse hit */
    pcl_f32 wox, woy, woz;    /* unit direction back along the arriving ray */
    pcl_u32 pixel;            /* y * width + x */
    pcl_f32 throughput[4];    /* rgb weight of the chain up to the hit, the lobe choice included */
    pcl_f32 albedo[4];        /* ρd rgb at the hit */
    pcl_f32 emitted[4];       /* the light the chain collects before its diffuse hit, rgb: Σ throughput ×
                                 Le over its hits (LE, LS+E), the glossy hits' direct light and, in
                                 media, the single-scattered light along its segments */
    pcl_u32 sample;           /* k: the sample within the pixel's pass */
    pcl_u32 material;         /* material index at the hit (0 when none) */
    pcl_u32 depth;            /* specular bounces before the hit */
    pcl_u32 flags;            /* PCL_EYE_DIFFUSE */
    pcl_f32 snx, sny, snz;    /* unit shading normal on the viewer's side (shared/shading_frame.h): the
                                 BSDF's frame and cosines; = (nx, ny, nz) on flat surfaces */
    pcl_u32 pad0;
} PclEyeHit;
PCL_STATIC_ASSERT(sizeof(PclEyeHit) == 128, PclEyeHit_size);

/* Radiance one stage gives one eye sample, rgb (W/(m² sr)); a is 0. */
typedef struct PclRadiance {
    pcl_f32 r, g, b, a;
} PclRadiance;
PCL_STATIC_ASSERT(sizeof(PclRadiance) == 16, PclRadiance_size);

/* accumulate (accumulate.cl): a chunk's records summed into one radiance per eye sample. */
#define PCL_ACCUMULATE_DIRECT 1u
#define PCL_ACCUMULATE_CAUSTIC 2u
#define PCL_ACCUMULATE_INDIRECT 4u
#define PCL_ACCUMULATE_VOLUME0 8u  /* the global volume map's part */
#define PCL_ACCUMULATE_VOLUME1 16u /* the volume caustic map's part */
typedef struct PclAccumulateParams {
    pcl_u32 firstPixel;       /* record i lies in pixel firstPixel + (firstSubsample + i) / n² */
    pcl_u32 firstSubsample;   /* record 0's sample within its pixel (< n²) */
    pcl_u32 sampleCount;      /* records in this launch */
    pcl_u32 samplesPerPixel;  /* n² */
    pcl_u32 width;            /* the image's */
    pcl_u32 parts;            /* PCL_ACCUMULATE_* bits: the parts this chunk got (the others are 0) */
    pcl_u32 emitterSpans;     /* 1: spans[2y], spans[2y + 1] bound row y's pixels [begin, end) whose
                                 emitted light the render's emitter samples give instead */
    pcl_u32 pad0;
} PclAccumulateParams;
PCL_STATIC_ASSERT(sizeof(PclAccumulateParams) == 32, PclAccumulateParams_size);

typedef struct PclDirectParams {
    pcl_u32 seedLo, seedHi;   /* the pass seed */
    pcl_u32 samplesPerPixel;  /* n² */
    pcl_u32 sampleCount;      /* eye records in this launch */
    pcl_u32 lightCount;
    pcl_u32 triangleCount;
    pcl_u32 lightSamples;     /* M: area-light samples per diffuse hit (0: delta lights only) */
    pcl_u32 gatherRays;       /* N: cosine samples stage 4 takes; 0 → light sampling alone, weight 1 */
    pcl_f32 areaPowerTotal;   /* Σ scalar power of the triangle lights (the choice's normaliser) */
    pcl_f32 rayEpsilon;
    pcl_u32 histogramCells;   /* G of the gather's importance histograms (MIS density); 0: cosine */
    pcl_u32 hasMedia;         /* 1: shadow rays carry the transmittance of media and invisible boundaries */
} PclDirectParams;
PCL_STATIC_ASSERT(sizeof(PclDirectParams) == 48, PclDirectParams_size);

typedef struct PclGatherParams {
    pcl_u32 seedLo, seedHi;   /* the pass seed */
    pcl_u32 samplesPerPixel;  /* n² */
    pcl_u32 sampleCount;      /* eye records; the launch covers sampleCount × gatherRays rays */
    pcl_u32 gatherRays;       /* N ≥ 1 */
    pcl_u32 triangleCount;
    pcl_u32 lightCount;
    pcl_u32 maxSpecular;      /* specular bounces a gather ray follows before giving up */
    pcl_u32 lightSamples;     /* M of direct_light (the MIS weight's other count) */
    pcl_u32 k;                /* written into each gather query */
    pcl_f32 maxRadius2;       /* written into each gather query */
    pcl_f32 areaPowerTotal;   /* as PclDirectParams */
    pcl_f32 rayEpsilon;
    pcl_u32 irradianceStride; /* resolve: floats per irradiance record (8: PclEstimate, 4: float4) */
    pcl_u32 histogramCells;   /* G: gather rays importance-sampled from a G × G incident-flux
                                 histogram per eye hit (final_gather_histogram); 0: cosine only */
    pcl_u32 causticMapRead;   /* 1: the caustic map is read at the eye hits, so light a gather ray
                                 reaches after a specular bounce (LS+D seen from the eye hit) is
                                 left to it, not counted twice */
    pcl_f32 closeDistance;    /* a gather ray whose diffuse hit lies nearer than this (the length of
                                 its path from the eye hit, mirrors and glass included) takes the
                                 direct light there by shadow rays and reads
                                 the map's other photons (PCL_QUERY_NONDIRECT); 0: none */
    pcl_u32 causticSky;       /* 1: the caustic map holds the sky's photons too, so with causticMapRead
                                 a gather ray's sky after a specular bounce is left to it; 0: the sky
                                 sent no caustic photons (PlanSettings::skyCaustics): counted here */
    pcl_u32 pad0, pad1;
} PclGatherParams;
/* The bounce word of the Philox block whose words 0 and 1 shift a pixel's copy of the pass's
 * gather pattern (stratify_shifted): above every k·N + g (n² ≤ 256, N ≤ 4096). */
#define PCL_GATHER_PATTERN_BOUNCE 0xFFFFFFFFu
/* The same for direct_light's patterns (stream LIGHT): above every k·M + m (M ≤ 256). */
#define PCL_LIGHT_PATTERN_BOUNCE 0xFFFFFFFFu
/* The path word of the Philox block that draws a pass's shared patterns (stratify_shifted) at
 * those bounce words: no pixel has this index. */
#define PCL_PASS_PATTERN_PATH 0xFFFFFFFFu
#define PCL_GATHER_UNIFORM_MIX 0.25f  /* the cosine share of the importance histogram's density */
#define PCL_GATHER_MAX_CELLS 16u      /* G ≤ 16 */
PCL_STATIC_ASSERT(sizeof(PclGatherParams) == 80, PclGatherParams_size);
/* The block words of a close gather hit's light samples (stream GATHER, path = pixel, bounce =
 * k·N + g): block PCL_GATHER_DIRECT_BLOCK u0 light choice, (u1, u2) its point; the next block
 * (u0, u1) the sky's direction. Above every b + 1 of the specular chain. */
#define PCL_GATHER_DIRECT_BLOCK 0xFFFFFF00u

/* What one gather ray found (final_gather_trace): its radiance toward the eye hit is
 * weight × E(query) + emitted. */
typedef struct PclGatherHit {
    pcl_f32 weight[4];        /* chain throughput × ρd/π at the gather hit's diffuse part; 0: none */
    pcl_f32 emitted[4];       /* chain throughput × Le × MIS weight of emitters met */
} PclGatherHit;
PCL_STATIC_ASSERT(sizeof(PclGatherHit) == 32, PclGatherHit_size);

/* Estimates at the eye hits (eye_estimate.cl): caustics, or the global map for preview. */
typedef struct PclEyeEstimateParams {
    pcl_u32 sampleCount;
    pcl_u32 k;
    pcl_f32 maxRadius2;
    pcl_u32 irradianceStride; /* floats per irradiance record (8: PclEstimate, 4: float4) */
    pcl_u32 minDepth;         /* records with fewer specular bounces before their hit get no estimate
                                 (1 under caustic connections: connect_caustics.cl lights those) */
    pcl_u32 atShutterOpen;    /* 1 for the global map: a hit on a moving surface asks where the surface
                                 sits at shutter open (shared/shutter_open.h); 0 for the caustic map */
    pcl_u32 pad1, pad2;
} PclEyeEstimateParams;
PCL_STATIC_ASSERT(sizeof(PclEyeEstimateParams) == 32, PclEyeEstimateParams_size);

/* ---- Caustic connections (connect_caustics.cl; kernels/README.md, "connect_caustics") ----
 * Each caustic photon (L S+ D) joined to the camera: the light tracer's splat (Veach 1997
 * §10.2) at the photon's diffuse vertex, instead of the caustic map's estimate at the eye hits
 * that see that surface directly. */
typedef struct PclConnectParams {
    pcl_u32 seedLo, seedHi;   /* the pass seed: lens samples (stream CONNECT, path = photon) */
    pcl_u32 photonCount;      /* caustic records in photons[] */
    pcl_u32 triangleCount;    /* global ids at or above it are spheres */
    pcl_f32 rayEpsilon;       /* spawn offset along the normal */
    pcl_f32 findDistance;     /* the record's surface is found again by a ray from p + n_f·d to p − n_f·d */
    pcl_u32 hasTimes;         /* 1: times[i] is photon i's shutter time (scenes that move); 0: all at 0 */
    pcl_u32 pad0;
} PclConnectParams;
PCL_STATIC_ASSERT(sizeof(PclConnectParams) == 32, PclConnectParams_size);

/* One connection: photon i's light in pixel `pixel`, rgb W/(m² sr) per pass (the pixel's average
 * radiance from that path); pixel = PCL_NO_SPLAT when the photon reaches no pixel (behind the
 * camera, off the film, occluded, facing away, surface not found again). */
#define PCL_NO_SPLAT 0xFFFFFFFFu
typedef struct PclSplat {
    pcl_u32 pixel;            /* y * width + x */
    pcl_f32 r, g, b;
} PclSplat;
PCL_STATIC_ASSERT(sizeof(PclSplat) == 16, PclSplat_size);

/* ---- Volume radiance estimate (volume_estimate.cl; kernels/README.md, "volume_estimate") ----
 * The beam radiance estimate (Jarosz, Zwicker & Jensen 2008) along the eye's PclVolumeSegments
 * from one volume photon map, searched through its hash grid (hashgrid.cl, cell size 2r). */
#define PCL_BEAM_KERNEL_BOX 0u      /* K = 1/(π r²) */
#define PCL_BEAM_KERNEL_BIWEIGHT 1u /* K = 3/(π r²) (1 − d²/r²)² (Silverman) */
typedef struct PclVolumeEstimateParams {
    pcl_f32 ox, oy, oz;          /* the hash grid's origin, cell size and table (PclGridParams) */
    pcl_f32 cellSize;            /* ≥ radius (the slab walk) */
    pcl_f32 invCellSize;
    pcl_u32 tableSize;
    pcl_u32 photonCount;
    pcl_f32 radius;              /* r: the map's reach, every photon's own radius r_p ≤ r */
    pcl_f32 radius2;             /* r² */
    pcl_f32 kernelNorm;          /* K's factor times r_p²: 1/π box, 3/π biweight */
    pcl_u32 kernelShape;         /* PCL_BEAM_KERNEL_* ("kernel" is an OpenCL C keyword) */
    pcl_u32 skipDirect;          /* 1: photons of bounce 0 (single scattering, done by NEE) do not count */
    pcl_u32 skipSpecularPaths;   /* 1: photons of L S+ V paths do not count (the volume caustic map has them) */
    pcl_u32 sampleCount;         /* eye records; segment k of record i at segments[k * sampleCount + i] */
    pcl_u32 maxSegments;         /* segmentCounts[i] ≤ this */
    pcl_u32 mediumCount;         /* entries of media[] */
} PclVolumeEstimateParams;
PCL_STATIC_ASSERT(sizeof(PclVolumeEstimateParams) == 64, PclVolumeEstimateParams_size);

/* ---- Image textures (shared/texture.h samples them; kernels/README.md, "Textures") ----------
 * Texels of every texture, linear RGB floats (three per texel, rows top to bottom), packed one
 * after another in one buffer. Each material has PCL_TEXTURE_SLOTS texture slots, described by
 * its PclMaterialTextures (indexed by material; a slot of width 0: untextured, the quantity is
 * the material's constant). Texture coordinates per triangle vertex in PclTriangleUv (indexed
 * by global primitive id; triangles only). */
#define PCL_WRAP_REPEAT 0u
#define PCL_WRAP_CLAMP 1u
#define PCL_WRAP_MIRROR 2u
typedef struct PclTexture {
    pcl_u32 offset;         /* index of the first texel's first float in the texel buffer */
    pcl_u32 width, height;  /* texels; width 0: no texture */
    pcl_u32 wrap;           /* PCL_WRAP_* of u in bits 0..7, of v in bits 8..15 */
    pcl_f32 m[6];           /* (u', v') = (m0 u + m1 v + m2, m3 u + m4 v + m5) (KHR_texture_transform) */
    pcl_u32 texCoord;       /* texture coordinate set, 0 or 1 */
    pcl_u32 pad0;
} PclTexture;
PCL_STATIC_ASSERT(sizeof(PclTexture) == 48, PclTexture_size);

#define PCL_TEXTURE_RHO_D 0    /* ρd = rhoD × texel (glTF: the base colour) */
#define PCL_TEXTURE_RHO_S 1    /* ρs = rhoS × texel */
#define PCL_TEXTURE_EXPONENT 2 /* Phong: exponent = lo + (hi − lo) R; metallic-roughness: B metallic, G roughness */
#define PCL_TEXTURE_EMISSION 3 /* emitted radiance = emission × texel (either mapping; glTF emissiveTexture) */
#define PCL_TEXTURE_SLOTS 4

#define PCL_TEXTURE_MAP_PHONG 0u              /* each slot scales its own quantity */
#define PCL_TEXTURE_MAP_METALLIC_ROUGHNESS 1u /* glTF: ρd, ρs and the exponent from base colour, metallic, roughness */
typedef struct PclMaterialTextures {
    PclTexture slot[PCL_TEXTURE_SLOTS]; /* by PCL_TEXTURE_* */
    pcl_u32 mapping;                    /* PCL_TEXTURE_MAP_* */
    pcl_f32 exponentLo, exponentHi;     /* Phong: the exponent's range over the texel's R in [0, 1] */
    pcl_f32 f0;                         /* metallic-roughness: the dielectric coat's F0 */
    pcl_f32 baseColor[4];               /* metallic-roughness: baseColorFactor rgb, [3] = 0 */
    pcl_f32 metallic, roughness;        /* metallic-roughness: metallicFactor, roughnessFactor */
    pcl_u32 pad0, pad1;
} PclMaterialTextures;
PCL_STATIC_ASSERT(sizeof(PclMaterialTextures) == 48 * PCL_TEXTURE_SLOTS + 48, PclMaterialTextures_size);

typedef struct PclTriangleUv {
    pcl_f32 uv[2][6];       /* set s: u0, v0, u1, v1, u2, v2 of the triangle's vertices 0, 1, 2 */
} PclTriangleUv;
PCL_STATIC_ASSERT(sizeof(PclTriangleUv) == 48, PclTriangleUv_size);

/* ---- Shading normals (shared/shading_frame.h; kernels/README.md, "Shading normals") --------
 * The vertex normals of every triangle (indexed by global primitive id; triangles only), on the
 * geometric normal's side or not: the lookup orients the interpolated one. All zero: the
 * triangle shades with its geometric normal (a mesh without normals). Uploaded only when some
 * mesh has normals that differ from its faces' (PCL_SHADING_NORMALS). */
typedef struct PclTriangleNormals {
    pcl_f32 n[9];           /* x0, y0, z0, x1, y1, z1, x2, y2, z2 of vertices 0, 1, 2 */
    pcl_f32 pad[3];
} PclTriangleNormals;
PCL_STATIC_ASSERT(sizeof(PclTriangleNormals) == 48, PclTriangleNormals_size);

/* ---- Normal maps (shared/shading_frame.h; kernels/README.md, "Normal maps") ----------------
 * A material's tangent-space normal map (indexed by material; texture width 0: none), its
 * texels in the texel buffer with the other textures; the vertex tangents of every triangle
 * (indexed by global primitive id; triangles only). Uploaded only when some material has a
 * normal map (PCL_NORMAL_MAPPED). */
typedef struct PclNormalMap {
    PclTexture texture;     /* linear rgb = (n + 1)/2 in tangent space */
    pcl_f32 scale;          /* glTF normalTexture.scale: multiplies the decoded x and y */
    pcl_u32 pad0, pad1, pad2;
} PclNormalMap;
PCL_STATIC_ASSERT(sizeof(PclNormalMap) == 64, PclNormalMap_size);

typedef struct PclTriangleTangents {
    pcl_f32 t[12];          /* x, y, z, w of vertices 0, 1, 2 (w = ±1: B = (N × T) w) */
} PclTriangleTangents;
PCL_STATIC_ASSERT(sizeof(PclTriangleTangents) == 48, PclTriangleTangents_size);

#endif /* PCL_TYPES_H */
