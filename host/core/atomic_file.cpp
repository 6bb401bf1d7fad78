#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace fs = std::filesystem;

namespace pcl {

std::string temporaryPathFor(const std::string& path) {
    static std::atomic<unsigned> counter{0};
    fs::path p(path);
    std::string name = "." + p.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                       std::to_string(counter++) + p.extension().string();
    return (p.parent_path() / name).string();
}

void writeThroughTemporary(const std::string& path, const std::function<void(const std::string&)>& write) {
    std::string tmp = temporaryPathFor(path);
    try {
        write(tmp);
        std::error_code ec;
        fs::rename(tmp, path, ec);
        if (ec) throw InputError(path + ": cannot write: " + ec.message());
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeThroughTemporary(path, [&](const std::string& tmp) {
        std::ofstream file(tmp, std::ios::binary);
        if (!file) throw InputError(path + ": cannot write: cannot open " + tmp);
        file.write(bytes.data(), std::streamsize(bytes.size()));
        file.close();
        if (!file) throw InputError(path + ": cannot write " + tmp + " (disk full?)");
    });
}

}  // namespace pcl
