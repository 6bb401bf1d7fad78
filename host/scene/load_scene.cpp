#include "scene/load_scene.h"

#include <cctype>

#include "scene/json_loader.h"
#include "scene/scene_error.h"
#include "scene/validate.h"
#ifdef PHOTONCL_HAVE_GLTF
#include "scene/gltf_loader.h"
#endif

namespace pcl {

namespace {
std::string extensionOf(const std::string& path) {
    auto dot = path.find_last_of('.');
    auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (auto& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}
}  // namespace

Scene loadScene(const std::string& path) {
    std::string ext = extensionOf(path);
    Scene scene;
    if (ext == ".json") {
        scene = loadJsonScene(path);
    } else if (ext == ".gltf" || ext == ".glb") {
#ifdef PHOTONCL_HAVE_GLTF
        scene = loadGltfScene(path);
#else
        failInput(path, "", "a .json scene (this photoncl was built without glTF support, PHOTONCL_WITH_GLTF=OFF)",
                  "a " + ext + " file");
#endif
    } else {
        failInput(path, "", "a scene file ending in .json, .gltf or .glb",
                  ext.empty() ? "no extension" : "\"" + ext + "\"");
    }
    validateScene(scene);
    return scene;
}

}  // namespace pcl
