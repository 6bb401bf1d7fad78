// Film, image files and error metrics: values and metadata survive a round trip, writers leave
// no temporary behind, and metrics equal hand-computed values.
#include <gtest/gtest.h>
#include "common/optional_feature.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "core/error.h"
#include "image/film.h"
#include "image/image_io.h"
#include "image/metrics.h"

namespace fs = std::filesystem;
using namespace pcl;

namespace {

// A fresh empty folder per test, removed afterwards.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("photoncl-image-test-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const std::string& name) const { return (path / name).string(); }
    size_t entries() const {
        return static_cast<size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator{}));
    }
};

Image gradient(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set(x, y, Vec3(0.25f * x + 0.001f, 3.5f * y, 1e-3f * (x + 7 * y) + 100.0f));
    return img;
}

}  // namespace

TEST(Film, AddResolveAndMerge) {
    Film a(2, 1), b(2, 1);
    a.add(0, 0, Vec3(1, 2, 3));
    a.add(0, 0, Vec3(3, 2, 1));       // mean (2,2,2)
    a.add(1, 0, Vec3(4, 0, 0), 0.5);  // weighted
    b.add(0, 0, Vec3(8, 8, 8), 2.0);  // after merge: (1+3+16, ..)/4
    Image ia = a.resolve();
    EXPECT_FLOAT_EQ(ia.at(0, 0).x, 2.0f);
    EXPECT_FLOAT_EQ(ia.at(1, 0).x, 4.0f);
    a.merge(b);
    Image im = a.resolve();
    EXPECT_FLOAT_EQ(im.at(0, 0).x, 20.0f / 4.0f);
    EXPECT_FLOAT_EQ(im.at(0, 0).z, 20.0f / 4.0f);
    EXPECT_DOUBLE_EQ(a.weight(0, 0), 4.0);
    EXPECT_DOUBLE_EQ(a.totalWeight(), 4.5);
    Film empty(1, 1);
    EXPECT_EQ(empty.resolve().at(0, 0).x, 0.0f);  // no sample: black, not NaN
    EXPECT_THROW(a.merge(Film(1, 2)), InputError);
    EXPECT_THROW(Film(0, 4), InputError);
}

TEST(Metrics, HandComputedValues) {
    Image a(2, 1), b(2, 1);
    a.set(0, 0, Vec3(1, 2, 3));
    a.set(1, 0, Vec3(0, 0, 0));
    b.set(0, 0, Vec3(1, 1, 1));
    b.set(1, 0, Vec3(0, 0, 2));
    // differences: 0, 1, 2, 0, 0, -2  → squared 0,1,4,0,0,4 (sum 9 over 6 values)
    ImageErrors e = compare(a, b);
    EXPECT_NEAR(e.rmse, std::sqrt(9.0 / 6.0), 1e-12);
    double rel = (0.0 / 1.01 + 1.0 / 1.01 + 4.0 / 1.01 + 0.0 / 0.01 + 0.0 / 0.01 + 4.0 / 4.01) / 6.0;
    EXPECT_NEAR(e.relMse, rel, 1e-9);
    EXPECT_NEAR(e.meanRatio, 6.0 / 5.0, 1e-12);
    EXPECT_DOUBLE_EQ(e.maxAbsDiff, 2.0);
    EXPECT_EQ(e.values, 6u);

    ImageErrors same = compare(b, b);
    EXPECT_EQ(same.rmse, 0.0);
    EXPECT_EQ(same.relMse, 0.0);
    EXPECT_EQ(same.meanRatio, 1.0);
    EXPECT_EQ(same.maxAbsDiff, 0.0);

    Image nan = b;
    nan.rgb[3] = NAN;
    EXPECT_TRUE(std::isnan(compare(nan, b).maxAbsDiff));  // NaNs are reported, not hidden
    EXPECT_THROW(compare(a, Image(1, 2)), InputError);
}

TEST(ImageIo, SrgbTransfer) {
    EXPECT_EQ(linearToSrgb(-1.0f), 0.0f);
    EXPECT_EQ(linearToSrgb(NAN), 0.0f);
    EXPECT_EQ(linearToSrgb(7.0f), 1.0f);
    EXPECT_NEAR(linearToSrgb(0.002f), 12.92f * 0.002f, 1e-7);
    EXPECT_NEAR(linearToSrgb(0.18f), 0.461356f, 1e-5);  // 18 % grey ≈ sRGB 118/255
    EXPECT_NEAR(linearToSrgb(0.5f), 0.735357f, 1e-5);
}

TEST(ImageIo, PfmRoundTripIsExact) {
    TempDir dir;
    Image img = gradient(5, 3);
    writePfm(dir.file("a.pfm"), img);
    Image back = readImage(dir.file("a.pfm"));
    ASSERT_EQ(back.width, 5);
    ASSERT_EQ(back.height, 3);
    EXPECT_EQ(back.rgb, img.rgb);
    EXPECT_EQ(dir.entries(), 1u);
}

TEST(ImageIo, LinearRoundTripKeepsValuesAndMetadata) {
    TempDir dir;
    Image img = gradient(7, 4);
    ImageMetadata meta;
    meta.scene = "scenes/cornell-box.json";
    meta.method = "path";
    meta.device = "ref";
    meta.samples = 1024;
    meta.seed = 18446744073709551557ull;  // needs all 64 bits
    meta.seconds = 12.5;
    std::string written = writeLinearImage(dir.file("out.exr"), img, meta);
    EXPECT_EQ(dir.entries(), 1u);  // the final file only: no temporary left behind
    ImageMetadata back;
    Image read = readImage(written, &back);
    ASSERT_EQ(read.width, 7);
    ASSERT_EQ(read.height, 4);
    EXPECT_EQ(read.rgb, img.rgb);  // float EXR (or PFM): bit exact
    if (haveOpenImageIO()) {
        EXPECT_EQ(written, dir.file("out.exr"));
        EXPECT_EQ(back.scene, meta.scene);
        EXPECT_EQ(back.method, "path");
        EXPECT_EQ(back.device, "ref");
        EXPECT_EQ(back.samples, 1024);
        EXPECT_EQ(back.seed, meta.seed);
        EXPECT_FLOAT_EQ(static_cast<float>(back.seconds), 12.5f);
        EXPECT_EQ(back.version, PHOTONCL_VERSION);

        // Half: values within half precision (11-bit mantissa: relative error ≤ 2^-11).
        std::string half = writeLinearImage(dir.file("half.exr"), img, meta, ExrPixelType::Half);
        Image h = readImage(half);
        for (size_t i = 0; i < img.rgb.size(); ++i)
            EXPECT_NEAR(h.rgb[i], img.rgb[i], std::abs(img.rgb[i]) * 4.9e-4 + 1e-7) << i;
    }
}

// Layers read back by name, bit exact, from the EXR (channels "<layer>.R/G/B") or, in a build
// without OpenImageIO, from the PFMs beside; a layer that is not there names itself.
TEST(ImageIo, LayersReadBackByName) {
    TempDir dir;
    Image img = gradient(6, 5), a = gradient(6, 5), b = gradient(6, 5);
    for (float& v : a.rgb) v = 2.0f * v + 1.0f;
    for (float& v : b.rgb) v = -v;
    const std::string written = writeLinearImage(dir.file("layers.exr"), img, ImageMetadata{}, {{"a", a}, {"b", b}});
    EXPECT_EQ(readImage(written).rgb, img.rgb);
    EXPECT_EQ(readImageLayer(written, "a").rgb, a.rgb);
    EXPECT_EQ(readImageLayer(written, "b").rgb, b.rgb);
    try {
        readImageLayer(written, "c");
        ADD_FAILURE() << "a missing layer was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("no layer 'c'"), std::string::npos) << e.what();
    }
    // The PFM form (what a build without OpenImageIO writes): "<stem>.<layer>.pfm" beside.
    writePfm(dir.file("p.pfm"), img);
    writePfm(dir.file("p.a.pfm"), a);
    EXPECT_EQ(readImageLayer(dir.file("p.pfm"), "a").rgb, a.rgb);
    EXPECT_THROW(readImageLayer(dir.file("p.pfm"), "b"), InputError);
}

TEST(ImageIo, PngWrittenInSrgb) {
    PCL_REQUIRE_FEATURE(haveOpenImageIO(), "OpenImageIO");
    TempDir dir;
    Image img(3, 1);
    img.set(0, 0, Vec3(0.0f, 0.18f, 1.0f));
    img.set(1, 0, Vec3(5.0f, -1.0f, 0.5f));
    img.set(2, 0, Vec3(0.002f, 0.0f, 0.0f));
    ASSERT_TRUE(writeSrgbPng(dir.file("out.png"), img));
    EXPECT_EQ(dir.entries(), 1u);
    Image png = readImage(dir.file("out.png"));  // read back as [0,1] floats
    ASSERT_EQ(png.width, 3);
    auto byte = [&](int x, int c) { return std::lround(png.at(x, 0)[c] * 255.0f); };
    EXPECT_EQ(byte(0, 0), 0);
    EXPECT_EQ(byte(0, 1), 118);  // 0.461356 * 255 = 117.6
    EXPECT_EQ(byte(0, 2), 255);
    EXPECT_EQ(byte(1, 0), 255);  // clamped
    EXPECT_EQ(byte(1, 1), 0);
    EXPECT_EQ(byte(1, 2), 188);  // 0.735357 * 255 = 187.5
    EXPECT_EQ(byte(2, 0), 7);    // linear segment: 12.92 * 0.002 * 255 = 6.6
}

TEST(ImageIo, FailedWriteLeavesNoFileAndKeepsTheOldOne) {
    TempDir dir;
    Image img = gradient(2, 2);
    // Into a folder that does not exist: InputError, nothing created.
    EXPECT_THROW(writeLinearImage(dir.file("missing/out.exr"), img, {}), InputError);
    EXPECT_THROW(writePfm(dir.file("missing/out.pfm"), img), InputError);
    // An empty image is refused before anything is written; a good file already there stays.
    std::string good = writeLinearImage(dir.file("keep.exr"), img, {});
    EXPECT_THROW(writeLinearImage(good, Image(), {}), InputError);
    EXPECT_EQ(readImage(good).rgb, img.rgb);
    EXPECT_EQ(dir.entries(), 1u);
}

TEST(ImageIo, ReadingBadFilesIsAnInputError) {
    TempDir dir;
    EXPECT_THROW(readImage(dir.file("nope.exr")), InputError);
    EXPECT_THROW(readImage(dir.file("nope.pfm")), InputError);
    {
        std::ofstream f(dir.file("bad.pfm"));
        f << "PF\n4 4\n-1.0\n0123";  // truncated pixels
    }
    EXPECT_THROW(readImage(dir.file("bad.pfm")), InputError);
    if (haveOpenImageIO()) {
        std::ofstream f(dir.file("bad.exr"));
        f << "not an exr";
        f.close();
        EXPECT_THROW(readImage(dir.file("bad.exr")), InputError);
    }
}
