// Files a scene refers to (a glTF from JSON, a buffer from glTF) must stay inside the folder of
// the file that names them: a scene is a self-contained folder that can be shipped to a render
// node, and a scene file must not be able to read /etc/passwd or ../../secrets.
#pragma once
#include <string>

namespace pcl {

// The folder part of `file` ("" when it has none).
std::string folderOf(const std::string& file);

// `uri` resolved against the folder of `referrer`. Throws InputError "REFERRER: FIELD: expected a
// relative path inside the scene's folder, got URI" for absolute paths, URI schemes, empty names
// and `..` segments that climb out of the folder.
std::string resolveInsideFolder(const std::string& referrer, const std::string& field, const std::string& uri);

// True when `path` (as produced by resolveInsideFolder or joined by tinygltf) lies lexically
// inside `folder`.
bool isInsideFolder(const std::string& folder, const std::string& path);

// glTF URIs are percent-encoded (RFC 3986); "%2e%2e" must be seen as ".." before checking.
std::string percentDecode(const std::string& uri);

}  // namespace pcl
