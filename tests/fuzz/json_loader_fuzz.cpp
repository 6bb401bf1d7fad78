// libFuzzer harness: arbitrary bytes as a JSON scene. Any outcome but a Scene or a pcl::InputError
// (a crash, a sanitizer report, another exception type, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <string>

#include "core/error.h"
#include "scene/json_loader.h"
#include "scene/validate.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    std::cerr.rdbuf(nullptr);  // loader warnings would flood the log; sanitizers write to fd 2 directly
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    try {
        // The folder does not exist: includes fail as missing files, never read real ones.
        pcl::Scene scene = pcl::parseJsonScene(text, "photoncl-fuzz-no-such-dir/scene.json");
        pcl::validateScene(scene);
    } catch (const pcl::InputError&) {
    }
    return 0;
}
