// libFuzzer harness: arbitrary bytes as a .gltf or .glb file (the loader tells them apart by the
// GLB magic). Any outcome but a Scene or a pcl::InputError is a bug.
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <vector>

#include "core/error.h"
#include "scene/gltf_loader.h"
#include "scene/validate.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    std::cerr.rdbuf(nullptr);  // loader warnings would flood the log; sanitizers write to fd 2 directly
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::vector<unsigned char> bytes(data, data + size);
    try {
        pcl::Scene scene;
        scene.path = "photoncl-fuzz-no-such-dir/scene.gltf";
        pcl::GltfImportResult r = pcl::importGltfFromMemory(scene, bytes, scene.path, pcl::GltfImportOptions{});
        if (r.hasCamera) scene.camera = r.camera;
        pcl::validateScene(scene);
    } catch (const pcl::InputError&) {
    }
    return 0;
}
