// Photon maps as PLY (host/pipeline/photon_ply.h, `photoncl photons`): the file round-trips the
// decoded photons, ASCII and binary agree, the header counts right, and the command writes the
// maps whole, deterministically, or not at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <string>

#include "pipeline/photon_ply.h"
#include "run_photoncl.h"
#include "shared/sampling.h"

namespace fs = std::filesystem;

namespace {

using namespace pcl;
using photoncl_cli::Result;
using photoncl_cli::run;

std::string scene(const std::string& name) { return std::string(PHOTONCL_SOURCE_DIR) + "/scenes/" + name; }

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string headerOf(const fs::path& p) {
    std::string bytes = readBytes(p);
    size_t end = bytes.find("end_header\n");
    return end == std::string::npos ? std::string() : bytes.substr(0, end + 11);
}

class PhotonPlyTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl_ply_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    fs::path dir;
};

struct Source {
    float px, py, pz, r, g, b, wx, wy, wz;
    uint32_t bounce;
};

// Random photons encoded as the kernels encode them, with the values they came from.
PhotonMaps randomMaps(size_t nGlobal, size_t nCaustic, std::vector<Source>* sources) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-10.0f, 10.0f), pw(1e-6f, 5.0f), dir(-1.0f, 1.0f);
    PhotonMaps maps;
    for (size_t i = 0; i < nGlobal + nCaustic; ++i) {
        Source s{pos(rng), pos(rng), pos(rng), pw(rng), pw(rng), pw(rng), 0, 0, 0, uint32_t(i % 7)};
        float wx, wy, wz, len;
        do {
            wx = dir(rng), wy = dir(rng), wz = dir(rng);
            len = std::sqrt(wx * wx + wy * wy + wz * wz);
        } while (len < 0.1f || len > 1.0f);
        s.wx = wx / len, s.wy = wy / len, s.wz = wz / len;
        if (i == 3) s.r = s.g = s.b = 0.0f;  // black photon: rgbe 0
        PclPhoton p;
        p.x = s.px, p.y = s.py, p.z = s.pz;
        p.rgbe = photon_rgbe_encode(s.r, s.g, s.b);
        p.packed = photon_dir_encode(s.wx, s.wy, s.wz) | (s.bounce << PCL_PHOTON_BOUNCE_SHIFT) |
                   (i >= nGlobal ? PCL_PHOTON_CAUSTIC : 0u) | (2u << PCL_PHOTON_AXIS_SHIFT);
        p.normal = photon_normal_encode(s.wz, -s.wx, s.wy);  // any unit vector
        (i < nGlobal ? maps.global : maps.caustic).push_back(p);
        if (sources) sources->push_back(s);
    }
    return maps;
}

PhotonPlyMetadata metadata() {
    PhotonPlyMetadata m;
    m.scene = "scenes/test.json";
    m.device = "test device";
    m.seed = 42;
    m.globalPhotons = 1000;
    m.causticPhotons = 500;
    return m;
}

void expectSame(const PlyPhoton& a, const PlyPhoton& b) {
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
    EXPECT_EQ(a.r, b.r);
    EXPECT_EQ(a.g, b.g);
    EXPECT_EQ(a.b, b.b);
    EXPECT_EQ(a.dx, b.dx);
    EXPECT_EQ(a.dy, b.dy);
    EXPECT_EQ(a.dz, b.dz);
    EXPECT_EQ(a.nx, b.nx);
    EXPECT_EQ(a.ny, b.ny);
    EXPECT_EQ(a.nz, b.nz);
    EXPECT_EQ(a.map, b.map);
    EXPECT_EQ(a.bounce, b.bounce);
}

TEST_F(PhotonPlyTest, RoundTripDecodesPhotons) {
    std::vector<Source> sources;
    PhotonMaps maps = randomMaps(300, 200, &sources);
    fs::path path = dir / "map.ply";
    writePhotonPly(path.string(), maps, metadata(), false);
    PhotonPly ply = readPhotonPly(path.string());
    EXPECT_FALSE(ply.ascii);
    ASSERT_EQ(ply.photons.size(), 500u);
    ASSERT_EQ(ply.declaredVertices, 500u);
    for (size_t i = 0; i < ply.photons.size(); ++i) {
        SCOPED_TRACE(i);
        const bool caustic = i >= 300;
        const PclPhoton& rec = caustic ? maps.caustic[i - 300] : maps.global[i];
        const PlyPhoton& p = ply.photons[i];
        expectSame(p, decodePhoton(rec, caustic ? kPlyMapCaustic : kPlyMapGlobal));
        EXPECT_EQ(p.map, caustic ? 1 : 0);
        EXPECT_EQ(p.bounce, sources[i].bounce);  // axis and flag bits do not leak into the bounce
        EXPECT_EQ(p.x, sources[i].px);
        EXPECT_EQ(p.y, sources[i].py);
        EXPECT_EQ(p.z, sources[i].pz);
        // Power: the record's RGBE bytes exactly (c = byte · 2^(E − 136)), and within RGBE's
        // precision (one step: the largest channel may round up to 256 and clamp to 255).
        const uint32_t E = rec.rgbe >> 24;
        const double step = E ? std::ldexp(1.0, int(E) - 136) : 0.0;
        EXPECT_DOUBLE_EQ(p.r, (rec.rgbe & 255u) * step);
        EXPECT_DOUBLE_EQ(p.g, ((rec.rgbe >> 8) & 255u) * step);
        EXPECT_DOUBLE_EQ(p.b, ((rec.rgbe >> 16) & 255u) * step);
        const double maxc = std::max({sources[i].r, sources[i].g, sources[i].b});
        EXPECT_NEAR(p.r, sources[i].r, step + 1e-6 * maxc);
        EXPECT_NEAR(p.g, sources[i].g, step + 1e-6 * maxc);
        EXPECT_NEAR(p.b, sources[i].b, step + 1e-6 * maxc);
        // Direction: unit, the centre of its byte cell, so within a cell's diagonal of the source.
        const double len = std::sqrt(double(p.dx) * p.dx + double(p.dy) * p.dy + double(p.dz) * p.dz);
        EXPECT_NEAR(len, 1.0, 1e-6);
        const double cosAngle = p.dx * sources[i].wx + p.dy * sources[i].wy + p.dz * sources[i].wz;
        EXPECT_GT(cosAngle, std::cos(0.03));
        // Normal: octahedral snorm16 keeps it within 1e-3 rad.
        const double cosN = p.nx * sources[i].wz - p.ny * sources[i].wx + p.nz * sources[i].wy;
        EXPECT_GT(cosN, std::cos(1e-3));
    }
    EXPECT_EQ(ply.photons[3].r, 0.0f);
}

TEST_F(PhotonPlyTest, AsciiAndBinaryAgree) {
    PhotonMaps maps = randomMaps(250, 120, nullptr);
    fs::path bin = dir / "bin.ply", txt = dir / "txt.ply";
    writePhotonPly(bin.string(), maps, metadata(), false);
    writePhotonPly(txt.string(), maps, metadata(), true);
    PhotonPly a = readPhotonPly(bin.string()), b = readPhotonPly(txt.string());
    EXPECT_FALSE(a.ascii);
    EXPECT_TRUE(b.ascii);
    EXPECT_EQ(a.comments, b.comments);
    ASSERT_EQ(a.photons.size(), b.photons.size());
    for (size_t i = 0; i < a.photons.size(); ++i) {
        SCOPED_TRACE(i);
        expectSame(a.photons[i], b.photons[i]);  // 9 significant digits read back to the same float
    }
    EXPECT_NE(headerOf(txt).find("format ascii 1.0\n"), std::string::npos);
    EXPECT_NE(headerOf(bin).find("format binary_little_endian 1.0\n"), std::string::npos);
    // Binary: header + 50 bytes a vertex (12 floats, 2 bytes), nothing else.
    EXPECT_EQ(readBytes(bin).size(), headerOf(bin).size() + 370u * 50u);
}

TEST_F(PhotonPlyTest, HeaderDeclaresCountsAndMetadata) {
    PhotonMaps maps = randomMaps(17, 5, nullptr);
    fs::path path = dir / "map.ply";
    writePhotonPly(path.string(), maps, metadata(), false);
    const std::string header = headerOf(path);
    EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\ncomment ", 0), 0u) << header;
    EXPECT_NE(header.find("element vertex 22\n"), std::string::npos) << header;
    for (const char* p : {"float x", "float y", "float z", "float r", "float g", "float b", "float dx", "float dy",
                          "float dz", "float nx", "float ny", "float nz", "uchar map", "uchar bounce"})
        EXPECT_NE(header.find(std::string("property ") + p + "\n"), std::string::npos) << p;
    PhotonPly ply = readPhotonPly(path.string());
    ASSERT_EQ(ply.comments.size(), 1u);
    const std::string& c = ply.comments[0];
    for (const char* s : {"scenes/test.json", "seed 42", "device test device", "global photons 1000 (17 stored)",
                          "caustic photons 500 (5 stored)"})
        EXPECT_NE(c.find(s), std::string::npos) << s << " in " << c;

    // Empty maps: a valid file with no vertices.
    fs::path empty = dir / "empty.ply";
    writePhotonPly(empty.string(), PhotonMaps{}, metadata(), true);
    EXPECT_NE(headerOf(empty).find("element vertex 0\n"), std::string::npos);
    EXPECT_TRUE(readPhotonPly(empty.string()).photons.empty());
}

TEST_F(PhotonPlyTest, WriterRejectsMissingFolder) {
    fs::path path = dir / "missing" / "map.ply";
    EXPECT_THROW(writePhotonPly(path.string(), randomMaps(3, 0, nullptr), metadata(), false), InputError);
    EXPECT_FALSE(fs::exists(path));
}

// The command: small counts on the CPU device.
std::string photonsArgs(const fs::path& out, uint64_t seed, const std::string& extra = "") {
    return "photons " + scene("cornell-spheres.json") + " -o " + out.string() +
           " --device cpu --global-photons 3000 --caustic-photons 2000 --seed " + std::to_string(seed) + " " + extra;
}

size_t storedFromSummary(const std::string& out, const std::string& kind) {
    std::smatch m;
    std::regex re(kind + ": [0-9]+ paths in [0-9]+ batches of [0-9]+, ([0-9]+) records");
    if (!std::regex_search(out, m, re)) return size_t(-1);
    return std::stoull(m[1].str());
}

TEST_F(PhotonPlyTest, CommandWritesBothMaps) {
    fs::path out = dir / "map.ply";
    Result r = run(photonsArgs(out, 5));
    ASSERT_EQ(r.status, 0) << r.output;
    PhotonPly ply = readPhotonPly(out.string());
    const size_t g = storedFromSummary(r.output, "global"), c = storedFromSummary(r.output, "caustic");
    ASSERT_NE(g, size_t(-1)) << r.output;
    ASSERT_NE(c, size_t(-1)) << r.output;
    EXPECT_GT(g, 0u);
    EXPECT_GT(c, 0u);  // cornell-spheres has a glass sphere: the plan builds a caustic map
    EXPECT_EQ(ply.declaredVertices, g + c);
    EXPECT_EQ(ply.photons.size(), g + c);
    size_t inGlobal = 0;
    for (const PlyPhoton& p : ply.photons) {
        ASSERT_LE(p.map, 1);
        inGlobal += p.map == 0;
        const double len = std::sqrt(double(p.dx) * p.dx + double(p.dy) * p.dy + double(p.dz) * p.dz);
        ASSERT_NEAR(len, 1.0, 1e-5);
        ASSERT_TRUE(std::isfinite(p.r) && p.r >= 0 && p.g >= 0 && p.b >= 0);
    }
    EXPECT_EQ(inGlobal, g);
    ASSERT_EQ(ply.comments.size(), 1u);
    EXPECT_NE(ply.comments[0].find("seed 5"), std::string::npos) << ply.comments[0];
    EXPECT_NE(ply.comments[0].find("global photons 3000"), std::string::npos) << ply.comments[0];
    EXPECT_NE(ply.comments[0].find("caustic photons 2000"), std::string::npos) << ply.comments[0];

    // --map caustic: only the caustic map, the same photons as above.
    fs::path caustic = dir / "caustic.ply";
    r = run(photonsArgs(caustic, 5, "--map caustic"));
    ASSERT_EQ(r.status, 0) << r.output;
    PhotonPly cp = readPhotonPly(caustic.string());
    EXPECT_EQ(cp.photons.size(), c);
    for (const PlyPhoton& p : cp.photons) ASSERT_EQ(p.map, 1);
}

TEST_F(PhotonPlyTest, CommandSameSeedSameBytesAsciiAgrees) {
    fs::path a = dir / "a.ply", b = dir / "b.ply", t = dir / "t.ply";
    ASSERT_EQ(run(photonsArgs(a, 9)).status, 0);
    ASSERT_EQ(run(photonsArgs(b, 9)).status, 0);
    const std::string bytes = readBytes(a);
    EXPECT_FALSE(bytes.empty());
    EXPECT_TRUE(bytes == readBytes(b)) << "same seed, different PLY bytes";
    Result r = run(photonsArgs(t, 9, "--ascii"));
    ASSERT_EQ(r.status, 0) << r.output;
    PhotonPly pb = readPhotonPly(a.string()), pt = readPhotonPly(t.string());
    EXPECT_TRUE(pt.ascii);
    ASSERT_EQ(pb.photons.size(), pt.photons.size());
    for (size_t i = 0; i < pb.photons.size(); ++i) {
        SCOPED_TRACE(i);
        expectSame(pb.photons[i], pt.photons[i]);
    }
}

TEST_F(PhotonPlyTest, CommandBadOutputFolderExits2) {
    fs::path out = dir / "no-such-folder" / "map.ply";
    Result r = run(photonsArgs(out, 1));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("no-such-folder"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(fs::is_empty(dir)) << "no temporary left behind";
}

TEST_F(PhotonPlyTest, CommandRejectsBadOptions) {
    EXPECT_EQ(run(photonsArgs(dir / "m.ply", 1, "--map nope")).status, 2);
    EXPECT_EQ(run("photons " + scene("cornell-spheres.json") + " --device cpu").status, 2);  // -o is required
    EXPECT_FALSE(fs::exists(dir / "m.ply"));
}

}  // namespace
