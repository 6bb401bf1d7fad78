#include "scene/scene_paths.h"

#include <vector>

#include "scene/scene_error.h"

namespace pcl {

std::string folderOf(const std::string& file) {
    auto slash = file.find_last_of('/');
    return slash == std::string::npos ? std::string() : file.substr(0, slash);
}

namespace {

// Splits on '/' and '\\' and applies "." and ".."; returns false when ".." climbs above the start.
bool normaliseRelative(const std::string& path, std::vector<std::string>& parts) {
    std::string part;
    auto flush = [&]() {
        if (part.empty() || part == ".") {
        } else if (part == "..") {
            if (parts.empty()) return false;
            parts.pop_back();
        } else {
            parts.push_back(part);
        }
        part.clear();
        return true;
    };
    for (char c : path) {
        if (c == '/' || c == '\\') {
            if (!flush()) return false;
        } else {
            part += c;
        }
    }
    return flush();
}

}  // namespace

std::string resolveInsideFolder(const std::string& referrer, const std::string& field, const std::string& uri) {
    const std::string expected = "a relative path inside the scene's folder";
    std::string shown = "\"" + uri + "\"";
    if (uri.empty()) failInput(referrer, field, expected, "an empty path");
    if (uri.find('\0') != std::string::npos) failInput(referrer, field, expected, "a path with a NUL byte");
    if (uri[0] == '/' || uri[0] == '\\') failInput(referrer, field, expected, shown + " (absolute)");
    // "C:..." drive letters and "file:", "http:" schemes: anything with ':' before the first '/'.
    auto colon = uri.find(':');
    if (colon != std::string::npos && colon < uri.find_first_of("/\\"))
        failInput(referrer, field, expected, shown + " (a URI scheme or drive)");
    std::vector<std::string> parts;
    if (!normaliseRelative(uri, parts) || parts.empty())
        failInput(referrer, field, expected, shown + " (leaves the folder)");
    std::string path = folderOf(referrer);
    for (const auto& p : parts) path += (path.empty() ? "" : "/") + p;
    return path;
}

bool isInsideFolder(const std::string& folder, const std::string& path) {
    std::string rest = path;
    if (!folder.empty()) {
        if (rest.compare(0, folder.size(), folder) != 0) return false;
        rest = rest.substr(folder.size());
        if (!rest.empty() && rest[0] != '/') return false;
    }
    while (rest.rfind("./", 0) == 0) rest = rest.substr(2);
    if (!rest.empty() && (rest[0] == '/' || rest[0] == '\\') && folder.empty()) return false;
    std::vector<std::string> parts;
    return normaliseRelative(rest, parts) && !parts.empty();
}

std::string percentDecode(const std::string& uri) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

}  // namespace pcl
