// Output files appear whole or not at all: a writer writes a temporary file in the
// destination folder, so the rename onto the final name is atomic, and removes it on failure.
#pragma once
#include <functional>
#include <string>

namespace pcl {

// "dir/.name.tmp-<pid>-<n>.ext": hidden, same folder, same extension (a format chosen by the
// extension, as OpenImageIO does, still applies to the temporary).
std::string temporaryPathFor(const std::string& path);

// Runs write(tmp), then renames tmp to path; on any failure removes tmp and rethrows.
void writeThroughTemporary(const std::string& path, const std::function<void(const std::string& tmp)>& write);

// The common case: `bytes` written through a temporary. Throws InputError naming `path`.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace pcl
