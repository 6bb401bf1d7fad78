#include "pipeline/photon_ply.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <system_error>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "shared/sampling.h"

namespace fs = std::filesystem;

namespace pcl {
namespace {

const char* const kProperties[] = {"float x",  "float y",  "float z",   "float r",     "float g",
                                   "float b",  "float dx", "float dy",  "float dz",    "float nx",
                                   "float ny", "float nz", "uchar map", "uchar bounce"};
constexpr int kFloats = 12;
constexpr size_t kBinaryVertexBytes = kFloats * 4 + 2;

// A comment is one header line: no line breaks inside.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

void putFloat(std::string& out, float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int i = 0; i < 4; ++i) out.push_back(char((u >> (8 * i)) & 255u));  // little-endian on any host
}

float getFloat(const unsigned char* b) {
    uint32_t u = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

void appendVertex(std::string& out, const PlyPhoton& p, bool ascii) {
    const float f[kFloats] = {p.x, p.y, p.z, p.r, p.g, p.b, p.dx, p.dy, p.dz, p.nx, p.ny, p.nz};
    if (ascii) {
        char buf[32];
        for (float v : f) {
            std::snprintf(buf, sizeof buf, "%.9g ", double(v));  // 9 digits: reads back to the same float
            out += buf;
        }
        std::snprintf(buf, sizeof buf, "%u %u\n", unsigned(p.map), unsigned(p.bounce));
        out += buf;
    } else {
        for (float v : f) putFloat(out, v);
        out.push_back(char(p.map));
        out.push_back(char(p.bounce));
    }
}

}  // namespace

PlyPhoton decodePhoton(const PclPhoton& p, uint8_t map) {
    PlyPhoton v;
    v.x = p.x;
    v.y = p.y;
    v.z = p.z;
    photon_rgbe_decode(p.rgbe, &v.r, &v.g, &v.b);
    PclV3 w = photon_dir_decode(p.packed);
    v.dx = w.x;
    v.dy = w.y;
    v.dz = w.z;
    PclV3 n = photon_normal_decode(p.normal);
    v.nx = n.x;
    v.ny = n.y;
    v.nz = n.z;
    v.map = map;
    v.bounce = uint8_t((p.packed >> PCL_PHOTON_BOUNCE_SHIFT) & 255u);
    return v;
}

void writePhotonPly(const std::string& path, const PhotonMaps& maps, const PhotonPlyMetadata& m, bool ascii) {
    fs::path dir = fs::path(path).parent_path();
    if (!dir.empty() && !fs::is_directory(dir))
        throw InputError(path + ": cannot write: output folder " + dir.string() + " does not exist");

    const size_t n = maps.global.size() + maps.caustic.size();
    std::string out;
    out += "ply\n";
    out += ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
    out += oneLine("comment photoncl photons: scene " + m.scene + ", seed " + std::to_string(m.seed) + ", device " +
                   m.device + ", global photons " + std::to_string(m.globalPhotons) + " (" +
                   std::to_string(maps.global.size()) + " stored), caustic photons " +
                   std::to_string(m.causticPhotons) + " (" + std::to_string(maps.caustic.size()) + " stored)") +
           "\n";
    out += "element vertex " + std::to_string(n) + "\n";
    for (const char* p : kProperties) out += std::string("property ") + p + "\n";
    out += "end_header\n";
    out.reserve(out.size() + n * (ascii ? 160 : kBinaryVertexBytes));
    for (const PclPhoton& p : maps.global) appendVertex(out, decodePhoton(p, kPlyMapGlobal), ascii);
    for (const PclPhoton& p : maps.caustic) appendVertex(out, decodePhoton(p, kPlyMapCaustic), ascii);

    writeFileAtomically(path, out);
}

PhotonPly readPhotonPly(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open");
    auto bad = [&](const std::string& why) { return InputError(path + ": not a photoncl photon PLY: " + why); };
    std::string line;
    if (!std::getline(in, line) || line != "ply") throw bad("no 'ply' magic");
    PhotonPly ply;
    bool haveFormat = false, haveCount = false;
    size_t property = 0;
    while (true) {
        if (!std::getline(in, line)) throw bad("header ends early");
        if (line == "end_header") break;
        if (line == "format ascii 1.0") {
            ply.ascii = true;
            haveFormat = true;
        } else if (line == "format binary_little_endian 1.0") {
            haveFormat = true;
        } else if (line.rfind("comment ", 0) == 0) {
            ply.comments.push_back(line.substr(8));
        } else if (line.rfind("element vertex ", 0) == 0) {
            ply.declaredVertices = std::stoull(line.substr(15));
            haveCount = true;
        } else if (line.rfind("property ", 0) == 0) {
            if (property >= std::size(kProperties) || line.substr(9) != kProperties[property])
                throw bad("unexpected '" + line + "'");
            ++property;
        } else {
            throw bad("unexpected header line '" + line + "'");
        }
    }
    if (!haveFormat || !haveCount || property != std::size(kProperties)) throw bad("incomplete header");

    ply.photons.resize(ply.declaredVertices);
    for (PlyPhoton& p : ply.photons) {
        float* f[kFloats] = {&p.x, &p.y, &p.z, &p.r, &p.g, &p.b, &p.dx, &p.dy, &p.dz, &p.nx, &p.ny, &p.nz};
        if (ply.ascii) {
            unsigned map = 0, bounce = 0;
            for (float* v : f) in >> *v;
            in >> map >> bounce;
            if (!in || map > 255 || bounce > 255) throw bad("bad ASCII vertex");
            p.map = uint8_t(map);
            p.bounce = uint8_t(bounce);
        } else {
            unsigned char b[kBinaryVertexBytes];
            if (!in.read(reinterpret_cast<char*>(b), sizeof b)) throw bad("fewer vertices than declared");
            for (int i = 0; i < kFloats; ++i) *f[i] = getFloat(b + 4 * i);
            p.map = b[4 * kFloats];
            p.bounce = b[4 * kFloats + 1];
        }
    }
    return ply;
}

}  // namespace pcl
