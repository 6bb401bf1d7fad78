// The JSON scene format (documented in scenes/README.md) → Scene.
#pragma once
#include <string>

#include "scene/scene.h"

namespace pcl {

// Reads and parses a JSON scene file. The result is not yet validated (loadScene does that).
Scene loadJsonScene(const std::string& path);

// Parses JSON scene text. `path` names the file in messages; glTF includes are resolved
// against its folder.
Scene parseJsonScene(const std::string& text, const std::string& path);

}  // namespace pcl
