// Shard files and fixed-point films: sums that add to the same bits in any
// grouping, a file format that round-trips exactly, and every truncation or flipped bit refused
// with the file's name and the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include <unistd.h>

#include "batch/shard_file.h"
#include "core/error.h"
#include "image/fixed_point_film.h"

namespace fs = std::filesystem;
using namespace pcl;

namespace {

// A pass film with noisy radiance spanning 1e-6 .. 1e4 (a lamp next to a dim corner).
Film randomPass(int w, int h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Film f(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int s = 0; s < 4; ++s) {
                float scale = std::pow(10.0f, -6.0f + 10.0f * u(rng));
                f.add(x, y, {scale * u(rng), scale * u(rng), scale * u(rng)});
            }
    return f;
}

ShardData sampleShard(int w, int h) {
    ShardData s;
    s.job = "jobs/x.json";
    s.index = 1;
    s.shards = 3;
    s.passes = 9;
    s.range = {3, 6};
    s.passesDone = 3;
    s.method = "fg";
    s.width = w;
    s.height = h;
    s.seed = 42;
    s.sceneHash = 0x0123456789abcdefull;
    s.settingsHash = 0xfedcba9876543210ull;
    s.settings = "method=fg;passes=9";
    s.version = "0.1.0";
    s.device = "test device";
    s.platform = "test platform";
    s.host = "here";
    s.globalEmitted = 123456;
    s.samples = 99;
    s.accounting["seconds"] = {{"total", 1.5}};
    s.film = FixedPointFilm(w, h);
    for (uint32_t p = 0; p < 3; ++p) s.film.addPass(randomPass(w, h, p));
    return s;
}

class ShardFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("photoncl-shard-file-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string refusal(const std::string& path) {
        try {
            readShardFile(path);
        } catch (const InputError& e) {
            return e.what();
        }
        return "(accepted)";
    }
    fs::path dir;
};

}  // namespace

TEST(FixedPointFilm, AnyGroupingOfPassesGivesTheSameBits) {
    const int w = 8, h = 6, passes = 12;
    std::vector<Film> pass;
    for (int p = 0; p < passes; ++p) pass.push_back(randomPass(w, h, 100 + p));
    FixedPointFilm all(w, h);
    for (const Film& f : pass) all.addPass(f);
    // Groupings: 1, 2, 3, 7 shards (as batch shards), each shard its own film, merged in reverse.
    for (int shards : {1, 2, 3, 7}) {
        std::vector<FixedPointFilm> parts;
        for (int i = 0; i < shards; ++i) {
            FixedPointFilm part(w, h);
            for (int p = i * passes / shards; p < (i + 1) * passes / shards; ++p) part.addPass(pass[size_t(p)]);
            parts.push_back(part);
        }
        FixedPointFilm merged(w, h);
        for (int i = shards - 1; i >= 0; --i) merged.add(parts[size_t(i)]);
        EXPECT_EQ(merged.sums(), all.sums()) << shards;
        EXPECT_EQ(merged.weights(), all.weights()) << shards;
        Image a = merged.resolve(), b = all.resolve(), viaDoubles = merged.toFilm().resolve();
        EXPECT_EQ(0, std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float))) << shards;
        EXPECT_EQ(0, std::memcmp(a.rgb.data(), viaDoubles.rgb.data(), a.rgb.size() * sizeof(float))) << shards;
    }
    // The doubles, by contrast, depend on the grouping: the reason for fixed point.
    Film seq(w, h), grouped(w, h), tail(w, h);
    for (const Film& f : pass) seq.merge(f);
    for (int p = 0; p < passes; ++p) (p < 5 ? grouped : tail).merge(pass[size_t(p)]);
    grouped.merge(tail);
    size_t differ = 0;
    for (size_t i = 0; i < seq.sums().size(); ++i) differ += seq.sums()[i] != grouped.sums()[i];
    std::printf("[figure] double sums differing between two groupings of 12 passes: %zu of %zu; fixed point: 0\n",
                differ, seq.sums().size());
}

TEST(FixedPointFilm, ResolvesWithinItsStepOfTheDoubleFilmAndRefusesNaN) {
    const int w = 8, h = 6;
    Film pass = randomPass(w, h, 7);
    FixedPointFilm fixed(w, h);
    fixed.addPass(pass);
    Film back = fixed.toFilm();
    double worst = 0;
    for (size_t i = 0; i < pass.sums().size(); ++i) worst = std::max(worst, std::fabs(back.sums()[i] - pass.sums()[i]));
    std::printf("[figure] fixed-point rounding: worst absolute error %.3g (bound 2^-33 = %.3g)\n", worst,
                0.5 / FixedPointFilm::kScale);
    EXPECT_LE(worst, 0.5 / FixedPointFilm::kScale * 1.0001);

    Film nan(1, 1);
    nan.add(0, 0, {std::nanf(""), 0, 0});
    EXPECT_THROW(FixedPointFilm(1, 1).addPass(nan), InputError);
}

// 128-bit sums: range ±2^95 ≈ 4.0e28 per pixel, still 2^-32 steps at every magnitude.
TEST(FixedPointFilm, HoldsSunlitSumsAndRefusesOverflowNamingThePixel) {
    auto pass = [](int w, int x, float v) {
        Film f(w, 1);
        f.add(x, 0, {v, v, v});
        return f;
    };
    // The sun seen directly in SI units (~2e7 W/(m² sr)) over 1000 one-sample passes: 2e10, ten
    // times the 64-bit film's range (2^31 ≈ 2.1e9); exact, as 2e7 is a whole number.
    FixedPointFilm sun(1, 1);
    for (int p = 0; p < 1000; ++p) sun.addPass(pass(1, 0, 2e7f));
    EXPECT_EQ(sun.toFilm().sums()[0], 2e10);
    EXPECT_EQ(sun.resolve().rgb[0], 2e7f);
    // Small fractions survive next to huge values: 1e20 + 0.5 − 1e20 is 0.5 exactly (doubles: 0).
    FixedPointFilm fine(1, 1);
    for (float v : {1e20f, 0.5f, -1e20f}) fine.addPass(pass(1, 0, v));
    EXPECT_EQ(fine.toFilm().sums()[0], 0.5);
    std::printf("[figure] fixed-point range: ±%.4g per pixel (2^95); 1000 passes of 2e7 sum to %.6g exactly; "
                "1e20 + 0.5 - 1e20 = %.3g\n",
                FixedPointFilm::kMaxValue, sun.toFilm().sums()[0], fine.toFilm().sums()[0]);

    auto refusal = [](auto&& what) -> std::string {
        try {
            what();
        } catch (const InputError& e) {
            return e.what();
        }
        return "(accepted)";
    };
    // One pass beyond the range: refused before rounding (1e30 > 2^95).
    FixedPointFilm f(3, 1);
    std::string why = refusal([&] { f.addPass(pass(3, 2, 1e30f)); });
    EXPECT_NE(why.find("pixel (2, 0)"), std::string::npos) << why;
    EXPECT_NE(why.find("±3.96e+28"), std::string::npos) << why;  // names the range
    // Totals: 3e28 twice is 6e28 > 2^95, either sign; refused, never wrapped.
    for (float v : {3e28f, -3e28f}) {
        FixedPointFilm g(3, 1);
        g.addPass(pass(3, 1, v));
        why = refusal([&] { g.addPass(pass(3, 1, v)); });
        EXPECT_NE(why.find("pixel (1, 0)"), std::string::npos) << v << ": " << why;
        EXPECT_EQ(g.toFilm().sums()[3], double(v)) << "the refused pass left the sum as it was";
    }
    // Two films near the limit (as shards merging): 2.5e28 + 2.5e28 overflows; 2.5e28 − 2.5e28 is 0.
    FixedPointFilm a(3, 1), b(3, 1), c(3, 1);
    a.addPass(pass(3, 0, 2.5e28f));
    b.addPass(pass(3, 0, 2.5e28f));
    c.addPass(pass(3, 0, -2.5e28f));
    why = refusal([&] { a.add(b); });
    std::printf("[figure] overflow refused: %s\n", why.c_str());
    EXPECT_NE(why.find("pixel (0, 0)"), std::string::npos) << why;
    b.add(c);
    EXPECT_EQ(b.toFilm().sums()[0], 0.0);
}

TEST_F(ShardFileTest, RoundTripsExactlyAndLeavesNoTemporary) {
    ShardData s = sampleShard(16, 9);
    std::string path = (dir / "shard-0001-of-0003.pcls").string();
    writeShardFile(path, s);
    ShardData r = readShardFile(path);
    EXPECT_EQ(r.film.sums(), s.film.sums());
    EXPECT_EQ(r.film.weights(), s.film.weights());
    EXPECT_EQ(r.index, 1u);
    EXPECT_EQ(r.shards, 3u);
    EXPECT_EQ(r.passes, 9u);
    EXPECT_EQ(r.range.first, 3u);
    EXPECT_EQ(r.range.end, 6u);
    EXPECT_TRUE(r.complete());
    EXPECT_EQ(r.sceneHash, s.sceneHash);
    EXPECT_EQ(r.settingsHash, s.settingsHash);
    EXPECT_EQ(r.settings, s.settings);
    EXPECT_EQ(r.device, "test device");
    EXPECT_EQ(r.globalEmitted, 123456u);
    EXPECT_DOUBLE_EQ(r.accounting["seconds"]["total"].get<double>(), 1.5);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temporary left
    // 128-bit values near the range, both signs, round-trip; each stored as its low then its high
    // 64 bits, little-endian (the first sum is the payload's first 16 bytes).
    ShardData big = sampleShard(2, 1);
    Film extreme(2, 1);
    extreme.add(0, 0, {3e28f, -1e25f, 0.25f});
    extreme.add(1, 0, {-3e28f, 7.0f, 1e-9f});
    big.film = FixedPointFilm(2, 1);
    big.film.addPass(extreme);
    std::string bigPath = (dir / "big.pcls").string();
    writeShardFile(bigPath, big);
    ShardData bigBack = readShardFile(bigPath);
    EXPECT_EQ(bigBack.film.sums(), big.film.sums());
    EXPECT_EQ(bigBack.film.weights(), big.film.weights());
    {
        std::ifstream in(bigPath, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        uint64_t headerBytes = 0, lo = 0, hi = 0;
        std::memcpy(&headerBytes, bytes.data() + 16, 8);
        std::memcpy(&lo, bytes.data() + 32 + headerBytes, 8);
        std::memcpy(&hi, bytes.data() + 32 + headerBytes + 8, 8);
        const FixedPointFilm::Fixed v = big.film.sums()[0];
        EXPECT_EQ(lo, uint64_t(v));
        EXPECT_EQ(hi, uint64_t(v >> 64));
        EXPECT_GT(hi, 0u);  // 3e28 · 2^32 needs the high half
    }
    fs::remove(bigPath);
    // Overwriting goes through a temporary too: the old file is replaced whole.
    s.passesDone = 2;
    writeShardFile(path, s);
    EXPECT_FALSE(readShardFile(path).complete());
}

TEST_F(ShardFileTest, TruncatedDamagedOrForeignFilesAreRefusedWithNameAndReason) {
    ShardData s = sampleShard(16, 9);
    std::string good = (dir / "good.pcls").string();
    writeShardFile(good, s);
    std::string bytes;
    {
        std::ifstream in(good, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    auto put = [&](const std::string& name, const std::string& content) {
        std::string p = (dir / name).string();
        std::ofstream(p, std::ios::binary) << content;
        return p;
    };
    int refused = 0, cases = 0;
    // Truncations: inside the prefix, the header, the payload, the checksum; and one byte extra.
    for (size_t keep :
         {size_t(0), size_t(10), size_t(40), size_t(200), bytes.size() / 2, bytes.size() - 9, bytes.size() - 1}) {
        std::string p = put("cut.pcls", bytes.substr(0, keep));
        std::string why = refusal(p);
        ++cases;
        refused += why.find(p) == 0;
        EXPECT_TRUE(why.find("truncated") != std::string::npos || why.find("not a photoncl shard") != std::string::npos)
            << keep << ": " << why;
    }
    EXPECT_NE(refusal(put("long.pcls", bytes + "x")).find("truncated or padded"), std::string::npos);
    // A flipped bit anywhere: magic, lengths, header, payload, checksum.
    std::mt19937 rng(5);
    for (int i = 0; i < 40; ++i) {
        size_t at = i < 8 ? size_t(i) * 5 : rng() % bytes.size();
        std::string damaged = bytes;
        damaged[at] = char(damaged[at] ^ (1 << (rng() % 8)));
        std::string p = put("flip.pcls", damaged);
        std::string why = refusal(p);
        ++cases;
        refused += why.find(p) == 0 && why != "(accepted)";
        EXPECT_NE(why, "(accepted)") << "flip at byte " << at;
    }
    EXPECT_NE(refusal(put("foreign.pcls", "P6\n1 1\n255\nabc")).find("not"), std::string::npos);
    // A shard of format version 1 (64-bit sums, before 128-bit fixed point): refused, both named.
    std::string v1 = bytes;
    v1[8] = 1;
    std::string old = put("v1.pcls", v1);
    std::string whyOld = refusal(old);
    std::printf("[figure] old shard refused: %s\n", whyOld.c_str());
    EXPECT_EQ(whyOld.find(old), 0u) << whyOld;
    EXPECT_NE(whyOld.find("version 1, expected version 2"), std::string::npos) << whyOld;
    EXPECT_NE(refusal((dir / "absent.pcls").string()).find("cannot be read"), std::string::npos);
    std::printf("[figure] damaged shard files refused with their name: %d of %d (7 truncations, 40 bit flips)\n",
                refused, cases);
    EXPECT_EQ(refused, cases);
}
