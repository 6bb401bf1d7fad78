#include "image/image_io.h"

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <system_error>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/error.h"

#ifdef PHOTONCL_HAVE_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

#ifndef PHOTONCL_VERSION
#define PHOTONCL_VERSION "unknown"
#endif

namespace fs = std::filesystem;

namespace pcl {
namespace {

void checkImage(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 || image.rgb.size() != image.pixelCount() * 3)
        throw InputError(path + ": cannot write an empty or malformed image (" + std::to_string(image.width) + "x" +
                         std::to_string(image.height) + ")");
}

[[maybe_unused]] std::string withExtension(const std::string& path, const char* ext) {
    return fs::path(path).replace_extension(ext).string();
}

bool isPfm(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".pfm";
}

#ifdef PHOTONCL_HAVE_OIIO
// Every channel of the first subimage as floats, interleaved; the file's spec beside them.
struct AllChannels {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;
};

// `proxy`: read from it instead of the file (path then names the format by its extension).
AllChannels readAllChannels(const std::string& path, OIIO::Filesystem::IOProxy* proxy = nullptr) {
    if (!proxy && !fs::exists(path)) throw InputError(path + ": no such file");
    auto in = OIIO::ImageInput::open(path, nullptr, proxy);
    if (!in) throw InputError(path + ": cannot read: " + OIIO::geterror());
    AllChannels a{in->spec(), {}};
    if (a.spec.width <= 0 || a.spec.height <= 0 || a.spec.nchannels <= 0)
        throw InputError(path + ": expected a non-empty image");
    a.pixels.resize(static_cast<size_t>(a.spec.width) * a.spec.height * a.spec.nchannels);
    if (!in->read_image(0, 0, 0, a.spec.nchannels, OIIO::TypeDesc::FLOAT, a.pixels.data()))
        throw InputError(path + ": cannot read pixels: " + in->geterror());
    in->close();
    return a;
}

StoredImage storedImage(AllChannels a) {
    StoredImage s;
    s.width = a.spec.width;
    s.height = a.spec.height;
    s.channels = a.spec.nchannels;
    s.integer = !a.spec.format.is_floating_point();
    s.pixels = std::move(a.pixels);
    return s;
}
#endif

}  // namespace

float linearToSrgb(float v) {
    if (!(v > 0.0f)) return 0.0f;  // also maps NaN to black
    if (v >= 1.0f) return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

bool haveOpenImageIO() {
#ifdef PHOTONCL_HAVE_OIIO
    return true;
#else
    return false;
#endif
}

// ---- PFM -------------------------------------------------------------------------------

void writePfm(const std::string& path, const Image& image) {
    checkImage(path, image);
    writeThroughTemporary(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw InputError(path + ": cannot write: cannot open " + tmp);
        out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";  // negative scale: little endian
        static_assert(sizeof(float) == 4, "PFM stores 4-byte floats");
        for (int y = image.height - 1; y >= 0; --y)  // PFM rows run bottom to top
            out.write(reinterpret_cast<const char*>(&image.rgb[static_cast<size_t>(y) * image.width * 3]),
                      static_cast<std::streamsize>(image.width) * 3 * sizeof(float));
        out.close();
        if (!out) throw InputError(path + ": cannot write: I/O error");
    });
}

Image readPfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open");
    std::string magic;
    long long w = 0, h = 0;
    double scale = 0.0;
    in >> magic >> w >> h >> scale;
    if (!in || (magic != "PF" && magic != "Pf") || w <= 0 || h <= 0 || w > (1 << 16) || h > (1 << 16) || scale == 0.0)
        throw InputError(path + ": expected a PFM header \"PF <width> <height> <scale>\"");
    if (scale > 0.0) throw InputError(path + ": big-endian PFM is not supported");
    in.get();  // the single whitespace character after the scale
    int channels = magic == "PF" ? 3 : 1;
    Image image(static_cast<int>(w), static_cast<int>(h));
    std::vector<float> row(static_cast<size_t>(w) * channels);
    for (long long y = h - 1; y >= 0; --y) {
        in.read(reinterpret_cast<char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(float)));
        if (!in) throw InputError(path + ": truncated PFM pixel data");
        for (long long x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                image.rgb[(static_cast<size_t>(y) * w + x) * 3 + c] =
                    row[static_cast<size_t>(x) * channels + (channels == 3 ? c : 0)];
    }
    return image;
}

// ---- EXR / PNG through OpenImageIO -------------------------------------------------------

#ifdef PHOTONCL_HAVE_OIIO
namespace {

void writeWithOiio(const std::string& path, const std::string& tmp, const OIIO::ImageSpec& spec, OIIO::TypeDesc inType,
                   const void* pixels) {
    // The format follows the final name's extension; the temporary keeps the same extension.
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw InputError(path + ": cannot write: " + OIIO::geterror());
    if (!out->open(tmp, spec) || !out->write_image(inType, pixels) || !out->close())
        throw InputError(path + ": cannot write: " + out->geterror());
}

}  // namespace
#endif

std::string writeLinearImage(const std::string& path, const Image& image, const ImageMetadata& metadata,
                             ExrPixelType type) {
    return writeLinearImage(path, image, metadata, {}, type);
}

std::string writeLinearImage(const std::string& path, const Image& image, const ImageMetadata& metadata,
                             const std::vector<ImageLayer>& layers, ExrPixelType type) {
    checkImage(path, image);
    for (const ImageLayer& l : layers) {
        if (l.name.empty() || l.name.find('.') != std::string::npos)
            throw InputError(path + ": layer name '" + l.name + "' must be non-empty and hold no '.'");
        if (l.image.width != image.width || l.image.height != image.height || l.image.rgb.size() != image.rgb.size())
            throw InputError(path + ": layer " + l.name + " is " + std::to_string(l.image.width) + "x" +
                             std::to_string(l.image.height) + ", the image " + std::to_string(image.width) + "x" +
                             std::to_string(image.height));
    }
#ifdef PHOTONCL_HAVE_OIIO
    const int channels = 3 + 3 * static_cast<int>(layers.size());
    OIIO::ImageSpec spec(image.width, image.height, channels,
                         type == ExrPixelType::Half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    if (!layers.empty()) {
        std::vector<std::string> names = {"R", "G", "B"};
        for (const ImageLayer& l : layers)
            for (const char* c : {"R", "G", "B"}) names.push_back(l.name + "." + c);
        spec.channelnames = names;
    }
    spec.attribute("compression", "zip");
    std::string version = metadata.version.empty() ? PHOTONCL_VERSION : metadata.version;
    spec.attribute("Software", "photoncl " + version);
    spec.attribute("photoncl:scene", metadata.scene);
    spec.attribute("photoncl:method", metadata.method);
    spec.attribute("photoncl:device", metadata.device);
    spec.attribute("photoncl:version", version);
    // 64-bit counts as decimal strings: EXR attributes hold 32-bit ints only.
    spec.attribute("photoncl:samples", std::to_string(metadata.samples));
    spec.attribute("photoncl:seed", std::to_string(metadata.seed));
    spec.attribute("photoncl:seconds", static_cast<float>(metadata.seconds));
    for (const auto& [key, value] : metadata.extra) spec.attribute("photoncl:" + key, value);
    std::vector<float> interleaved;
    const float* pixels = image.rgb.data();
    if (!layers.empty()) {
        interleaved.resize(image.pixelCount() * channels);
        for (size_t i = 0; i < image.pixelCount(); ++i) {
            float* out = &interleaved[i * channels];
            for (int c = 0; c < 3; ++c) out[c] = image.rgb[3 * i + c];
            for (size_t l = 0; l < layers.size(); ++l)
                for (int c = 0; c < 3; ++c) out[3 + 3 * l + c] = layers[l].image.rgb[3 * i + c];
        }
        pixels = interleaved.data();
    }
    writeThroughTemporary(path, [&](const std::string& tmp) {
        writeWithOiio(path, tmp, spec, OIIO::TypeDesc::FLOAT, pixels);
    });
    return path;
#else
    (void)metadata;
    (void)type;
    std::string pfm = withExtension(path, ".pfm");
    writePfm(pfm, image);
    for (const ImageLayer& l : layers) writePfm(withExtension(path, ("." + l.name + ".pfm").c_str()), l.image);
    return pfm;
#endif
}

bool writeSrgbPng(const std::string& path, const Image& image) {
    checkImage(path, image);
#ifdef PHOTONCL_HAVE_OIIO
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<unsigned char>(std::lround(linearToSrgb(image.rgb[i]) * 255.0f));
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    writeThroughTemporary(path, [&](const std::string& tmp) {
        writeWithOiio(path, tmp, spec, OIIO::TypeDesc::UINT8, bytes.data());
    });
    return true;
#else
    return false;
#endif
}

Image readImageLayer(const std::string& path, const std::string& layer) {
    if (isPfm(path)) {
        const std::string beside = withExtension(path, ("." + layer + ".pfm").c_str());  // as the writer names it
        if (!fs::exists(beside)) throw InputError(path + ": no layer '" + layer + "' (" + beside + ")");
        return readPfm(beside);
    }
#ifdef PHOTONCL_HAVE_OIIO
    const AllChannels a = readAllChannels(path);
    const int channels = a.spec.nchannels;
    int first[3] = {-1, -1, -1};
    std::string found;
    for (int c = 0; c < channels; ++c) {
        const std::string& name = a.spec.channelnames[c];
        found += (found.empty() ? "" : ", ") + name;
        for (int k = 0; k < 3; ++k)
            if (name == layer + "." + "RGB"[k]) first[k] = c;
    }
    if (first[0] < 0 || first[1] < 0 || first[2] < 0)
        throw InputError(path + ": no layer '" + layer + "': expected channels " + layer + ".R, .G, .B; found " +
                         found);
    Image image(a.spec.width, a.spec.height);
    for (size_t i = 0; i < image.pixelCount(); ++i)
        for (int k = 0; k < 3; ++k) image.rgb[3 * i + k] = a.pixels[i * channels + first[k]];
    return image;
#else
    throw InputError(path + ": this build reads PFM only (built without OpenImageIO)");
#endif
}

StoredImage readStoredImage(const std::string& path) {
    StoredImage s;
    if (isPfm(path)) {
        const Image image = readPfm(path);
        s.width = image.width;
        s.height = image.height;
        s.channels = 3;
        s.pixels = image.rgb;
        return s;
    }
#ifdef PHOTONCL_HAVE_OIIO
    return storedImage(readAllChannels(path));
#else
    throw InputError(path + ": this build reads PFM only (built without OpenImageIO)");
#endif
}

StoredImage readStoredImage(const std::vector<unsigned char>& bytes, const std::string& name) {
#ifdef PHOTONCL_HAVE_OIIO
    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    return storedImage(readAllChannels(name, &memory));
#else
    (void)bytes;
    throw InputError(name + ": this build reads no embedded images (built without OpenImageIO)");
#endif
}

Image readImage(const std::string& path, ImageMetadata* metadata) {
    if (isPfm(path)) {
        if (metadata) *metadata = ImageMetadata{};
        return readPfm(path);
    }
#ifdef PHOTONCL_HAVE_OIIO
    const AllChannels a = readAllChannels(path);
    const OIIO::ImageSpec& spec = a.spec;
    const std::vector<float>& pixels = a.pixels;
    const int channels = spec.nchannels;
    Image image(spec.width, spec.height);
    for (size_t i = 0; i < image.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = pixels[i * channels + (channels >= 3 ? c : 0)];
    if (metadata) {
        ImageMetadata m;
        m.scene = spec.get_string_attribute("photoncl:scene");
        m.method = spec.get_string_attribute("photoncl:method");
        m.device = spec.get_string_attribute("photoncl:device");
        m.version = spec.get_string_attribute("photoncl:version");
        // A string as photoncl writes it, or an integer as `oiiotool --attrib` writes a number.
        const OIIO::ParamValue* samples = spec.find_attribute("photoncl:samples");
        m.samples = !samples ? 0
                    : samples->type() == OIIO::TypeString
                        ? std::strtoll(spec.get_string_attribute("photoncl:samples").c_str(), nullptr, 10)
                        : spec.get_int_attribute("photoncl:samples", 0);
        m.seed = std::strtoull(spec.get_string_attribute("photoncl:seed", "0").c_str(), nullptr, 10);
        m.seconds = spec.get_float_attribute("photoncl:seconds", 0.0f);
        // The other photoncl: string attributes (settings, photons, stage times...) come back as extras.
        static const std::set<std::string> kNamed = {"scene",   "method", "device", "version",
                                                     "samples", "seed",   "seconds"};
        for (const OIIO::ParamValue& p : spec.extra_attribs) {
            const std::string name = p.name().string();
            if (name.rfind("photoncl:", 0) != 0 || kNamed.count(name.substr(9)) || p.type() != OIIO::TypeString)
                continue;
            m.extra.emplace_back(name.substr(9), spec.get_string_attribute(name));
        }
        *metadata = m;
    }
    return image;
#else
    throw InputError(path + ": this build reads PFM only (built without OpenImageIO)");
#endif
}

}  // namespace pcl
