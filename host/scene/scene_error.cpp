#include "scene/scene_error.h"

#include <iostream>

namespace pcl {

void failInput(const std::string& file, const std::string& field, const std::string& expected, const std::string& got) {
    std::string message = file + ": ";
    if (!field.empty()) message += field + ": ";
    message += "expected " + expected + ", got " + got;
    throw InputError(message);
}

void warnInput(const std::string& file, const std::string& message) {
    std::cerr << "warning: " << file << ": " << message << "\n";
}

}  // namespace pcl
