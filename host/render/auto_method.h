// `render --method auto`: fg or the path tracer, whichever a short pilot says reaches a lower
// error in the same time on this scene at this size. Each method renders the image at a quarter
// of its width and height twice with independent seeds (fg one pass each, with the settings the
// full render would use; the path tracer 16 samples per pixel each). The variance of one render
// is half the relMSE between the two; times its cost at full size (the photon pass and the maps
// cost the same at any size, the eye work and the path tracer scale with the pixels) it is the
// error × seconds product that equal-time comparisons measure. The lower product wins. What the
// pilot cannot see: fg's bias (its estimates are blurred, not noisy: cornell-box's fg is 0.2 %
// dark), and noise that only finer pixels resolve.
#pragma once
#include <string>

#include "device/device.h"
#include "prep/prepared_scene.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace pcl {

struct AutoMethodChoice {
    RenderMethod method = RenderMethod::FinalGather;
    double fgErrorSeconds = 0, pathErrorSeconds = 0;  // relMSE × seconds at full size, per method
    double fgPassSeconds = 0, pathSampleSeconds = 0;  // the full image's pass / sample per pixel, predicted
    double pilotSeconds = 0;                          // wall time of the whole pilot
    std::string log() const;                          // one line: the choice and its figures
};

// The pilot on `device` (fg) and the CPU (path tracer) for `request` at the scene camera's size.
AutoMethodChoice chooseRenderMethod(Device& device, const Scene& scene, const PreparedScene& prepared,
                                    const RenderRequest& request);

}  // namespace pcl
