#include "prep/media_support.h"

#include <set>

#include "scene/scene_error.h"

namespace pcl {

void refuseMediaWithoutPathTracer(const Scene& scene, const std::string& what) {
    if (!scene.hasMedia()) return;
    std::set<std::string> used;
    if (scene.globalMedium >= 0) used.insert("\"" + scene.media[size_t(scene.globalMedium)].name + "\" (global)");
    for (const auto& m : scene.meshes)
        if (m.medium >= 0) used.insert("\"" + scene.media[size_t(m.medium)].name + "\" in " + m.name);
    for (const auto& s : scene.spheres)
        if (s.medium >= 0) used.insert("\"" + scene.media[size_t(s.medium)].name + "\" in " + s.name);
    std::string got;
    for (const std::string& u : used) got += (got.empty() ? "" : ", ") + u;
    failInput(scene.path, "medium",
              "a scene without participating media for " + what +
                  " (media are rendered by --method progressive, direct and path)",
              "media " + got);
}

}  // namespace pcl
