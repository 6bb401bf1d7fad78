// How the scene loaders report bad input: one message shape everywhere,
// "FILE: FIELD: expected X, got Y" (README.md, "Commands": exit statuses), thrown as pcl::InputError (exit status 2).
#pragma once
#include <string>

#include "core/error.h"

namespace pcl {

// Throws InputError("FILE: FIELD: expected EXPECTED, got GOT"). FIELD may be empty for errors
// about the file as a whole.
[[noreturn]] void failInput(const std::string& file, const std::string& field, const std::string& expected,
                            const std::string& got);

// A warning about input that is accepted but changed (dropped triangles, ignored textures):
// one line on stderr, "warning: FILE: MESSAGE".
void warnInput(const std::string& file, const std::string& message);

}  // namespace pcl
