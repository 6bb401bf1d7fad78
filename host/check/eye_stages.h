// `photoncl check SCENE --stage eye_paths` and `--stage direct_light`: the eye paths and the
// direct light on the device against their CPU twins on a small image (the scene's camera
// resized), one pass, in any scene, participating media included (kernels/README.md, "Eye
// pass: media"). Each stage runs on the same inputs: the eye paths on the device's camera rays,
// the direct light on the device's eye records. The eye-paths report also compares the medium
// segments (scenes with media): per record, the count, medium and record index must be equal,
// then every segment's origin, length, direction, time and throughput match as values do in
// check/render.h (|d − t| ≤ tolerance · max(|d|, |t|) + 1e-6 · peak).
#pragma once
#include <vector>

#include "check/render.h"
#include "device/device.h"
#include "prep/prepared_scene.h"
#include "reference/eye_paths.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace pcl {

// The segments of record i as values (slot-major input: segments[c · records + i]): perRecord ×
// 11 values (origin, length, direction, time, throughput rgb; zeros past the record's count),
// then a 0/1 "same count, media and record indices" value (twin 1, device 1 when equal).
StageComparison compareEyeSegments(const EyeVolumeSegments& device, const EyeVolumeSegments& twin, double tolerance,
                                   size_t worstShown);

// Rows: camera rays, eye paths, medium segments (scenes with media).
RenderCheckReport checkEyePathsStage(Device& device, const Scene& scene, const PreparedScene& prepared,
                                     const RenderCheckOptions& options = {});
// Rows: direct light (from the device's eye records).
RenderCheckReport checkDirectLightStage(Device& device, const Scene& scene, const PreparedScene& prepared,
                                        const RenderCheckOptions& options = {});

// Rows: each caustic photon's connection to the camera (pixel and value, record by record) and
// the film they add up to, from one device caustic pass of options.causticPhotons paths.
RenderCheckReport checkConnectCausticsStage(Device& device, const Scene& scene, const PreparedScene& prepared,
                                            const RenderCheckOptions& options = {});

}  // namespace pcl
