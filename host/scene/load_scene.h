// The one entry point for scene files: dispatch on the extension, then validate.
#pragma once
#include <string>

#include "scene/scene.h"

namespace pcl {

// Loads .json, .gltf or .glb; throws InputError (exit status 2) on any bad input.
Scene loadScene(const std::string& path);

}  // namespace pcl
