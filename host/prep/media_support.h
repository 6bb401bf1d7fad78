// The photon methods (fg, direct, progressive, auto) and the device stages do not model
// participating media yet: until the volume photon map lands (issue 17) they refuse a scene
// with a medium instead of rendering it as if the medium were not there. The reference path
// tracer (--method path) renders media.
#pragma once
#include <string>

#include "scene/scene.h"

namespace pcl {

// Throws InputError "SCENE: medium: expected a scene without participating media for WHAT (...),
// got ..." when scene.hasMedia(); `what` names the method or command ("--method fg", "check").
void refuseMediaWithoutPathTracer(const Scene& scene, const std::string& what);

}  // namespace pcl
