// Image files: linear OpenEXR with the render's metadata, an sRGB 8-bit PNG for viewing, and
// PFM (raw float) where OpenImageIO is absent (the lent GPU machine). Every writer writes a
// temporary file in the destination folder and renames it, so the final name holds either
// nothing or a complete file (no partial file in place of a good one: core/atomic_file.h).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"

namespace pcl {

// Stored as EXR attributes "photoncl:scene", "photoncl:method", ... (and "Software").
struct ImageMetadata {
    std::string scene;    // scene file
    std::string method;   // path | fg | direct | progressive
    std::string device;   // device name, or "ref"
    std::string version;  // photoncl version; empty: this build's PHOTONCL_VERSION
    int64_t samples = 0;  // samples (or passes) per pixel
    uint64_t seed = 0;
    double seconds = 0.0;  // render wall time
    // More attributes, written as "photoncl:<key>" strings (settings, photons, passes, seconds
    // per stage). EXR only; readImage does not read them back.
    std::vector<std::pair<std::string, std::string>> extra;
};

// An extra layer of a multi-channel EXR (AOVs: direct, caustic, albedo, ...): channels
// "<name>.R", "<name>.G", "<name>.B" after the main R, G, B. Same size as the main image.
struct ImageLayer {
    std::string name;
    Image image;
};

enum class ExrPixelType { Half, Float };

// True when this build writes EXR/PNG (OpenImageIO found at configure time).
bool haveOpenImageIO();

// Writes a linear image. With OpenImageIO: OpenEXR (zip compression) at `path`, metadata as
// attributes. Without it: PFM at `path` with its extension replaced by ".pfm" (PFM holds no
// metadata). Returns the path actually written. Throws InputError if it cannot be written.
std::string writeLinearImage(const std::string& path, const Image& image, const ImageMetadata& metadata,
                             ExrPixelType type = ExrPixelType::Float);
// The same with extra layers in the one EXR. Without OpenImageIO the layers are written beside
// the PFM as "<stem>.<layer>.pfm". A layer of another size, or named "" / with a '.', is an
// InputError.
std::string writeLinearImage(const std::string& path, const Image& image, const ImageMetadata& metadata,
                             const std::vector<ImageLayer>& layers, ExrPixelType type = ExrPixelType::Float);

// sRGB 8-bit PNG: exposure 1, the sRGB transfer function (IEC 61966-2-1), clamped to [0,1].
// Returns false (writes nothing) in a build without OpenImageIO.
bool writeSrgbPng(const std::string& path, const Image& image);

// Reads RGB (the first three channels; a one-channel image is replicated) from any file
// OpenImageIO reads, or from PFM in any build. Fills metadata when asked and present.
Image readImage(const std::string& path, ImageMetadata* metadata = nullptr);

// An image as its file stores it, for textures: every channel (interleaved, as floats; integer
// formats normalised to [0,1]) and whether the file holds integers (8/16-bit: display-encoded,
// sRGB by convention) or floats (linear). InputError when it cannot be read or is empty.
struct StoredImage {
    int width = 0, height = 0, channels = 0;
    bool integer = false;
    std::vector<float> pixels;  // width * height * channels, top row first
};
StoredImage readStoredImage(const std::string& path);
// The same from an encoded file's bytes in memory (an image embedded in a glTF file); `name`
// only tells OpenImageIO the format by its extension (".png", ".jpg"). InputError without
// OpenImageIO.
StoredImage readStoredImage(const std::vector<unsigned char>& bytes, const std::string& name);

// One layer written by writeLinearImage with layers: the channels "<layer>.R/G/B" of an EXR, or
// the PFM "<stem>.<layer>.pfm" beside a PFM. InputError naming the layer when it is not there.
Image readImageLayer(const std::string& path, const std::string& layer);

// PFM ("PF", little-endian, bottom row first), always available.
void writePfm(const std::string& path, const Image& image);
Image readPfm(const std::string& path);

// The sRGB encoding of one linear value, in [0,1] (exposed for tests).
float linearToSrgb(float linear);

}  // namespace pcl
