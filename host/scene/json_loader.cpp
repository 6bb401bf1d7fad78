// Reads the JSON scene format of scenes/README.md. Every field is checked where it is read, so a
// message can name the JSON path: "scenes/x.json: materials[2].rho_d: expected 3 numbers in
// [0,1], got [1.2,0,0]". Checks that span the whole scene live in validate.cpp.
#include "scene/json_loader.h"
#include "core/math.h"

#include <cctype>
#include <cmath>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "image/image_io.h"
#include "scene/json_parse.h"
#include "scene/scene_error.h"
#include "scene/scene_paths.h"
#include "scene/texture_image.h"
#include "scene/transform.h"
#ifdef PHOTONCL_HAVE_GLTF
#include "scene/gltf_loader.h"
#endif

namespace pcl {

namespace {

using json = nlohmann::json;
constexpr double kFloatMax = 3.0e38;  // numbers beyond this would become inf as float

std::string keyPath(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string indexPath(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }
std::string join(std::initializer_list<const char*> names) {
    std::string s;
    for (const char* n : names) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}
bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

class JsonSceneReader {
public:
    explicit JsonSceneReader(std::string file) : file_(std::move(file)) { scene_.path = file_; }

    Scene read(const json& root) {
        checkObject(root, "",
                    {"comment", "camera", "materials", "media", "medium", "shapes", "lights", "environment",
                     "include"});
        if (auto* v = optional(root, "comment")) text(*v, "comment");
        if (auto* v = optional(root, "media")) {
            for (size_t i = 0; i < array(*v, "media").size(); ++i) readMedium((*v)[i], indexPath("media", i));
        }
        if (auto* v = optional(root, "medium")) scene_.globalMedium = mediumRef(*v, "medium");
        if (auto* v = optional(root, "materials")) {
            for (size_t i = 0; i < array(*v, "materials").size(); ++i) readMaterial((*v)[i], indexPath("materials", i));
        }
        if (auto* v = optional(root, "shapes")) {
            for (size_t i = 0; i < array(*v, "shapes").size(); ++i) readShape((*v)[i], indexPath("shapes", i));
        }
        if (auto* v = optional(root, "lights")) {
            for (size_t i = 0; i < array(*v, "lights").size(); ++i) readLight((*v)[i], indexPath("lights", i));
        }
        if (auto* v = optional(root, "environment")) readEnvironment(*v, "environment");
        if (auto* v = optional(root, "include")) readIncludes(*v, "include");
        if (auto* v = optional(root, "camera")) {
            readCamera(*v, "camera");
        } else if (includedCamera_) {
            scene_.camera = *includedCamera_;
        } else {
            failInput(file_, "camera", "a camera object (or an included glTF with a camera)", "none");
        }
        return std::move(scene_);
    }

private:
    [[noreturn]] void fail(const std::string& field, const std::string& expected, const json& got) {
        failInput(file_, field, expected, showJson(got));
    }

    // ---- Generic field readers -----------------------------------------------------------

    // `value` must be an object whose keys are all in `allowed`.
    void checkObject(const json& value, const std::string& path, std::initializer_list<const char*> allowed) {
        if (!value.is_object()) fail(path.empty() ? "(top level)" : path, "an object", value);
        for (auto it = value.begin(); it != value.end(); ++it) {
            bool known = false;
            for (const char* a : allowed) known = known || it.key() == a;
            if (!known)
                failInput(file_, keyPath(path, it.key()), "one of the keys " + join(allowed),
                          "unknown key \"" + it.key() + "\"");
        }
    }
    const json* optional(const json& object, const char* key) {
        auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }
    const json& required(const json& object, const std::string& path, const char* key, const std::string& expected) {
        auto it = object.find(key);
        if (it == object.end()) failInput(file_, keyPath(path, key), expected, "nothing (the key is missing)");
        return *it;
    }
    const json& array(const json& value, const std::string& path) {
        if (!value.is_array()) fail(path, "an array", value);
        return value;
    }
    double number(const json& value, const std::string& path, double lo, double hi, const std::string& expected) {
        if (!value.is_number()) fail(path, expected, value);
        double x = value.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi) fail(path, expected, value);
        return x;
    }
    std::string text(const json& value, const std::string& path) {
        if (!value.is_string()) fail(path, "a string", value);
        return value.get<std::string>();
    }
    // Three numbers, each in [lo, hi].
    Vec3 triple(const json& value, const std::string& path, double lo, double hi, const std::string& expected) {
        if (!value.is_array() || value.size() != 3) fail(path, expected, value);
        Vec3 v;
        for (int i = 0; i < 3; ++i) {
            if (!value[i].is_number()) fail(path, expected, value);
            double x = value[i].get<double>();
            if (!std::isfinite(x) || x < lo || x > hi) fail(path, expected, value);
            v[i] = float(x);
        }
        return v;
    }
    Vec3 point(const json& value, const std::string& path) {
        return triple(value, path, -kFloatMax, kFloatMax, "3 finite numbers");
    }
    Vec3 direction(const json& value, const std::string& path) {
        Vec3 d = triple(value, path, -kFloatMax, kFloatMax, "3 finite numbers, not all zero");
        double l = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
        if (!(l > 0) || !std::isfinite(l)) fail(path, "3 finite numbers, not all zero", value);
        return Vec3(float(d.x / l), float(d.y / l), float(d.z / l));
    }
    Vec3 reflectance(const json& value, const std::string& path) {
        return triple(value, path, 0.0, 1.0, "3 numbers in [0,1]");
    }
    Vec3 radiometric(const json& value, const std::string& path) {  // powers, radiances: ≥ 0
        return triple(value, path, 0.0, kFloatMax, "3 finite numbers >= 0");
    }
    // Like radiometric() but a light of zero power is refused: it would never be sampled.
    Vec3 lightAmount(const json& value, const std::string& path) {
        Vec3 v = radiometric(value, path);
        if (maxComponent(v) <= 0) fail(path, "3 finite numbers >= 0, not all zero (a light must emit)", value);
        return v;
    }
    Vec3 motion(const json& object, const std::string& path) {
        auto* v = optional(object, "motion");
        return v ? point(*v, keyPath(path, "motion")) : Vec3(0.0f);
    }

    int materialRef(const json& value, const std::string& path) {
        std::string name = text(value, path);
        auto it = materialIndex_.find(name);
        if (it == materialIndex_.end()) {
            std::string names;
            for (const auto& [n, i] : materialIndex_) names += (names.empty() ? "" : ", ") + n;
            failInput(file_, path, "the name of a material (" + (names.empty() ? "none defined" : names) + ")",
                      "\"" + name + "\"");
        }
        return it->second;
    }

    // {"translate": [x,y,z], "rotate": {"axis": [x,y,z], "degrees": a}, "scale": s | [x,y,z]}
    // applied as T·R·S, or {"matrix": 16 numbers, row-major}.
    Transform transform(const json& value, const std::string& path) {
        checkObject(value, path, {"translate", "rotate", "scale", "matrix"});
        Transform t;
        if (auto* m = optional(value, "matrix")) {
            if (value.size() != 1) failInput(file_, path, "either \"matrix\" or translate/rotate/scale", "both");
            const std::string expected = "16 finite numbers (row-major 4x4, last row 0 0 0 1)";
            if (!m->is_array() || m->size() != 16) fail(keyPath(path, "matrix"), expected, *m);
            double v[16];
            for (int i = 0; i < 16; ++i)
                v[i] = number((*m)[i], keyPath(path, "matrix"), -kFloatMax, kFloatMax, expected);
            if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) fail(keyPath(path, "matrix"), expected, *m);
            t = Transform::rowMajor(v);
        } else {
            if (auto* s = optional(value, "scale")) {
                const std::string expected = "a non-zero number or 3 non-zero numbers";
                Vec3 k;
                if (s->is_number()) {
                    k = Vec3(float(number(*s, keyPath(path, "scale"), -kFloatMax, kFloatMax, expected)));
                } else {
                    k = triple(*s, keyPath(path, "scale"), -kFloatMax, kFloatMax, expected);
                }
                if (k.x == 0 || k.y == 0 || k.z == 0) fail(keyPath(path, "scale"), expected, *s);
                t = Transform::scale(k.x, k.y, k.z);
            }
            if (auto* r = optional(value, "rotate")) {
                std::string rp = keyPath(path, "rotate");
                checkObject(*r, rp, {"axis", "degrees"});
                Vec3 axis = direction(required(*r, rp, "axis", "3 finite numbers, not all zero"), keyPath(rp, "axis"));
                double deg = number(required(*r, rp, "degrees", "a number"), keyPath(rp, "degrees"), -1e6, 1e6,
                                    "a number of degrees");
                t = Transform::rotate(deg, axis.x, axis.y, axis.z) * t;
            }
            if (auto* tr = optional(value, "translate")) {
                Vec3 d = point(*tr, keyPath(path, "translate"));
                t = Transform::translate(d.x, d.y, d.z) * t;
            }
        }
        if (!t.isFinite() || t.determinant3() == 0) failInput(file_, path, "an invertible transform", "a singular one");
        return t;
    }

    // ---- Materials -------------------------------------------------------------------------

    void readMaterial(const json& value, const std::string& path) {
        checkObject(value, path, {"name", "rho_d", "specular", "emission", "normal_map"});
        Material m;
        m.name = text(required(value, path, "name", "a material name"), keyPath(path, "name"));
        if (m.name.empty()) fail(keyPath(path, "name"), "a non-empty name", value["name"]);
        if (materialIndex_.count(m.name))
            failInput(file_, keyPath(path, "name"), "a name not used by another material", "\"" + m.name + "\" again");
        if (auto* v = optional(value, "rho_d")) {
            if (v->is_object()) {
                m.rhoDTexture = readReflectanceTexture(*v, keyPath(path, "rho_d"), m.rhoD);
            } else {
                m.rhoD = reflectance(*v, keyPath(path, "rho_d"));
            }
        }
        if (auto* v = optional(value, "normal_map")) readNormalMap(*v, keyPath(path, "normal_map"), m);
        if (auto* v = optional(value, "emission")) {
            if (v->is_object()) {
                m.emissionTexture = readEmissionTexture(*v, keyPath(path, "emission"), m.emission);
            } else {
                m.emission = radiometric(*v, keyPath(path, "emission"));
            }
        }
        if (auto* s = optional(value, "specular")) readSpecular(*s, keyPath(path, "specular"), m);
        Vec3 sum = m.rhoD + m.rhoS;
        if (maxComponent(sum) > 1.0f + 1e-6f) {
            json shown = {sum.x, sum.y, sum.z};
            failInput(file_, path, "rho_d + rho_s <= 1 in every channel (energy conservation)",
                      "rho_d + rho_s = " + showJson(shown));
        }
        materialIndex_[m.name] = int(scene_.materials.size());
        scene_.materials.push_back(m);
    }

    // {"texture": "wood.png", "factor": [r,g,b], ...the texture's keys (readTexture)}: a
    // reflectance (ρd or ρs) = factor × the texture. Returns its Scene::textures index.
    int readReflectanceTexture(const json& value, const std::string& path, Vec3& factor) {
        const int t = readTexture(value, path, "factor", TextureEncoding::Auto);
        factor = Vec3(1.0f);
        if (auto* f = optional(value, "factor")) factor = reflectance(*f, keyPath(path, "factor"));
        return t;
    }

    // {"texture": "sign.png", "factor": [r,g,b], ...the texture's keys}: emitted radiance =
    // factor (W m^-2 sr^-1, ≥ 0, default 1) × the texture (sRGB for 8/16-bit files by default).
    int readEmissionTexture(const json& value, const std::string& path, Vec3& factor) {
        const int t = readTexture(value, path, "factor", TextureEncoding::Auto);
        factor = Vec3(1.0f);
        if (auto* f = optional(value, "factor")) factor = radiometric(*f, keyPath(path, "factor"));
        return t;
    }

    // {"texture": "shine.png", "range": [lo, hi], ...the texture's keys}: the glossy exponent =
    // lo + (hi − lo) × the texture's R (linear unless "encoding" says srgb), 0 < lo ≤ hi ≤ 1e6.
    int readExponentTexture(const json& value, const std::string& path, float range[2]) {
        const int t = readTexture(value, path, "range", TextureEncoding::Linear);
        const std::string rp = keyPath(path, "range");
        const std::string expected = "2 numbers lo, hi with 0 < lo <= hi <= 1e6";
        const json& r = required(value, path, "range", expected);
        if (!r.is_array() || r.size() != 2) fail(rp, expected, r);
        for (int i = 0; i < 2; ++i) range[i] = float(number(r[size_t(i)], rp, 0.0, 1e6, expected));
        if (!(range[0] > 0.0f) || range[1] < range[0]) fail(rp, expected, r);
        return t;
    }

    // {"texture": "bumps.png", "normal_scale": s, ...the texture's keys}: a tangent-space normal
    // map (glTF's normalTexture; "scale" is the coordinates' scale as for every texture, so glTF's
    // normalTexture.scale is "normal_scale" here, default 1). Linear unless "encoding" says
    // otherwise: a normal map stores vectors, not colours.
    void readNormalMap(const json& value, const std::string& path, Material& m) {
        if (!value.is_object()) fail(path, "an object {\"texture\": FILE, ...}", value);
        m.normalTexture = readTexture(value, path, "normal_scale", TextureEncoding::Linear);
        if (auto* s = optional(value, "normal_scale"))
            m.normalScale = float(number(*s, keyPath(path, "normal_scale"), -1e6, 1e6, "a number"));
    }

    // {"texture": "wood.png", "wrap": "repeat" | "clamp" | "mirror" | [u, v], "offset": [u, v],
    // "scale": [u, v], "rotation": degrees, "encoding": "srgb" | "linear"} and the caller's own
    // key `own`: an image beside the scene file. Returns its Scene::textures index.
    int readTexture(const json& value, const std::string& path, const char* own, TextureEncoding defaultEncoding) {
        checkObject(value, path, {"texture", own, "wrap", "offset", "scale", "rotation", "encoding"});
        Texture t;
        const std::string field = keyPath(path, "texture");
        const std::string name = text(required(value, path, "texture", "an image file name"), field);
        t.path = resolveInsideFolder(file_, field, name);
        TextureEncoding encoding = defaultEncoding;
        if (auto* e = optional(value, "encoding")) {
            const std::string kind = text(*e, keyPath(path, "encoding"));
            if (kind == "srgb") encoding = TextureEncoding::Srgb;
            else if (kind == "linear") encoding = TextureEncoding::Linear;
            else fail(keyPath(path, "encoding"), "srgb or linear", *e);
        }
        t.image = loadTextureImage(file_, field, t.path, encoding);
        if (auto* w = optional(value, "wrap")) {
            const std::string wp = keyPath(path, "wrap");
            if (w->is_array()) {
                if (w->size() != 2) fail(wp, "a wrap mode or two (u, v)", *w);
                t.wrapU = wrapMode((*w)[0], indexPath(wp, 0));
                t.wrapV = wrapMode((*w)[1], indexPath(wp, 1));
            } else {
                t.wrapU = t.wrapV = wrapMode(*w, wp);
            }
        }
        if (auto* o = optional(value, "offset")) pair(*o, keyPath(path, "offset"), t.transform.offset);
        if (auto* k = optional(value, "scale")) pair(*k, keyPath(path, "scale"), t.transform.scale);
        if (auto* r = optional(value, "rotation"))
            t.transform.rotation =
                float(number(*r, keyPath(path, "rotation"), -1e6, 1e6, "a number of degrees") * kPiD / 180.0);
        scene_.textures.push_back(std::move(t));
        return int(scene_.textures.size()) - 1;
    }
    TextureWrap wrapMode(const json& value, const std::string& path) {
        const std::string w = value.is_string() ? value.get<std::string>() : "";
        if (w == "repeat") return TextureWrap::Repeat;
        if (w == "clamp") return TextureWrap::Clamp;
        if (w == "mirror") return TextureWrap::Mirror;
        fail(path, "repeat, clamp or mirror", value);
    }
    void pair(const json& value, const std::string& path, float out[2]) {
        const std::string expected = "2 finite numbers";
        if (!value.is_array() || value.size() != 2) fail(path, expected, value);
        for (int i = 0; i < 2; ++i) out[i] = float(number(value[size_t(i)], path, -1e30, 1e30, expected));
    }

    // A mirror's or glossy lobe's "rho_s": 3 numbers in [0, 1], or a texture object (ρs = factor × it).
    void readRhoS(const json& value, const std::string& path, Material& m) {
        const json& v = required(value, path, "rho_s", "3 numbers in [0,1] or a texture object");
        if (v.is_object()) m.rhoSTexture = readReflectanceTexture(v, keyPath(path, "rho_s"), m.rhoS);
        else m.rhoS = reflectance(v, keyPath(path, "rho_s"));
    }

    void readSpecular(const json& value, const std::string& path, Material& m) {
        if (!value.is_object()) fail(path, "an object", value);
        std::string kind = text(required(value, path, "kind", "mirror, glossy or dielectric"), keyPath(path, "kind"));
        if (kind == "mirror") {
            checkObject(value, path, {"kind", "rho_s"});
            m.specular = SpecularKind::Mirror;
            readRhoS(value, path, m);
        } else if (kind == "glossy") {
            checkObject(value, path, {"kind", "rho_s", "exponent"});
            m.specular = SpecularKind::Glossy;
            readRhoS(value, path, m);
            const json& e = required(value, path, "exponent", "a number in (0, 1e6] or a texture object");
            if (e.is_object()) {
                m.exponentTexture = readExponentTexture(e, keyPath(path, "exponent"), m.exponentRange);
                m.phongExponent = m.exponentRange[1];  // the sharpest lobe it reaches (for whatever needs one number)
            } else {
                m.phongExponent =
                    float(number(e, keyPath(path, "exponent"), 0.0, 1e6, "a number in (0, 1e6] or a texture object"));
                if (m.phongExponent <= 0)
                    fail(keyPath(path, "exponent"), "a number in (0, 1e6] or a texture object", value["exponent"]);
            }
        } else if (kind == "dielectric") {
            checkObject(value, path, {"kind", "rho_s", "ior"});
            m.specular = SpecularKind::Dielectric;
            m.rhoS = Vec3(1.0f);
            if (auto* v = optional(value, "rho_s")) m.rhoS = reflectance(*v, keyPath(path, "rho_s"));
            if (auto* v = optional(value, "ior")) {
                m.ior = float(number(*v, keyPath(path, "ior"), 1e-3, 10.0, "a number in (0, 10]"));
            }
        } else {
            fail(keyPath(path, "kind"), "one of mirror, glossy, dielectric", value["kind"]);
        }
    }

    // ---- Environment -----------------------------------------------------------------------

    // {"radiance": [r,g,b]} (constant), or {"image": "sky.exr", "scale": s | [r,g,b], "rotation":
    // degrees about +y}: an equirectangular linear image (EXR, HDR, PFM) beside the scene file.
    void readEnvironment(const json& value, const std::string& path) {
        checkObject(value, path, {"radiance", "image", "scale", "rotation"});
        Environment& env = scene_.environment;
        auto* image = optional(value, "image");
        auto* radiance = optional(value, "radiance");
        if ((image != nullptr) == (radiance != nullptr))
            failInput(file_, path, "either \"radiance\" (a constant sky) or \"image\" (an equirectangular map)",
                      image ? "both" : "neither");
        if (radiance) {
            if (optional(value, "scale"))
                failInput(file_, keyPath(path, "scale"), "no scale with a constant radiance (give the radiance)",
                          "a scale");
            env.scale = lightAmount(*radiance, keyPath(path, "radiance"));
        } else {
            const std::string field = keyPath(path, "image");
            const std::string name = text(*image, field);
            const std::string lower = [&] {
                std::string l = name;
                for (char& c : l) c = char(std::tolower(static_cast<unsigned char>(c)));
                return l;
            }();
            if (!endsWith(lower, ".exr") && !endsWith(lower, ".hdr") && !endsWith(lower, ".pfm"))
                failInput(file_, field, "a linear HDR image (.exr, .hdr or .pfm)", "\"" + name + "\"");
            env.imagePath = resolveInsideFolder(file_, field, name);
            try {
                env.image = readImage(env.imagePath);
            } catch (const std::exception& e) {
                failInput(file_, field, "a readable image", std::string("\"") + name + "\" (" + e.what() + ")");
            }
            if (env.image.width < 1 || env.image.height < 1)
                failInput(file_, field, "an image of at least 1x1 texels",
                          std::to_string(env.image.width) + "x" + std::to_string(env.image.height));
            for (size_t i = 0; i < env.image.rgb.size(); ++i)
                if (!std::isfinite(env.image.rgb[i]) || env.image.rgb[i] < 0.0f) {
                    const size_t texel = i / 3;
                    failInput(file_, field, "finite texels >= 0",
                              std::to_string(env.image.rgb[i]) + " at texel (" +
                                  std::to_string(texel % size_t(env.image.width)) + ", " +
                                  std::to_string(texel / size_t(env.image.width)) + ")");
                }
            env.scale = Vec3(1.0f);
            if (auto* k = optional(value, "scale")) {
                const std::string expected = "a number > 0 or 3 numbers >= 0, not all zero";
                env.scale = k->is_number() ? Vec3(float(number(*k, keyPath(path, "scale"), 0.0, kFloatMax, expected)))
                                           : lightAmount(*k, keyPath(path, "scale"));
                if (!env.active()) fail(keyPath(path, "scale"), expected, *k);
            }
            bool emits = false;
            for (float x : env.image.rgb) emits = emits || x > 0.0f;
            if (!emits) failInput(file_, field, "an image with some light in it", "all texels zero");
        }
        if (auto* r = optional(value, "rotation"))
            env.rotationDegrees = float(number(*r, keyPath(path, "rotation"), -1e6, 1e6, "a number of degrees"));
    }

    // ---- Media ---------------------------------------------------------------------------

    // {"name": ..., "sigma_a": [r,g,b], "sigma_s": [r,g,b], "g": g}: 1/m, |g| < 1.
    void readMedium(const json& value, const std::string& path) {
        checkObject(value, path, {"name", "sigma_a", "sigma_s", "g"});
        Medium m;
        m.name = text(required(value, path, "name", "a medium name"), keyPath(path, "name"));
        if (m.name.empty()) fail(keyPath(path, "name"), "a non-empty name", value["name"]);
        if (mediumIndex_.count(m.name))
            failInput(file_, keyPath(path, "name"), "a name not used by another medium", "\"" + m.name + "\" again");
        const std::string coefficient = "3 finite numbers >= 0 (1/m)";
        if (auto* v = optional(value, "sigma_a"))
            m.sigmaA = triple(*v, keyPath(path, "sigma_a"), 0.0, kFloatMax, coefficient);
        if (auto* v = optional(value, "sigma_s"))
            m.sigmaS = triple(*v, keyPath(path, "sigma_s"), 0.0, kFloatMax, coefficient);
        if (maxComponent(m.sigmaA + m.sigmaS) <= 0)
            failInput(file_, path, "sigma_a + sigma_s > 0 in some channel (a medium that does nothing is no medium)",
                      "all zero");
        if (auto* v = optional(value, "g")) {
            const std::string expected = "a Henyey-Greenstein g in (-1, 1)";
            m.g = float(number(*v, keyPath(path, "g"), -1.0, 1.0, expected));
            if (!(std::abs(m.g) < 1.0f)) fail(keyPath(path, "g"), expected, *v);
        }
        mediumIndex_[m.name] = int(scene_.media.size());
        scene_.media.push_back(m);
    }

    int mediumRef(const json& value, const std::string& path) {
        std::string name = text(value, path);
        auto it = mediumIndex_.find(name);
        if (it == mediumIndex_.end()) {
            std::string names;
            for (const auto& [n, i] : mediumIndex_) names += (names.empty() ? "" : ", ") + n;
            failInput(file_, path, "the name of a medium (" + (names.empty() ? "none defined" : names) + ")",
                      "\"" + name + "\"");
        }
        return it->second;
    }

    // A shape's "medium" (or -1), read before its material: with a medium, "material" may be left
    // out and the shape is then an invisible boundary (Material::interface).
    int shapeMedium(const json& value, const std::string& path) {
        auto* v = optional(value, "medium");
        return v ? mediumRef(*v, keyPath(path, "medium")) : -1;
    }
    int shapeMaterial(const json& value, const std::string& path, int medium) {
        if (medium >= 0 && !value.contains("material")) return interfaceMaterial();
        return materialRef(required(value, path, "material",
                                    medium >= 0 ? "a material name (or none: an invisible medium boundary)"
                                                : "a material name"),
                           keyPath(path, "material"));
    }
    // The one material of every invisible medium boundary, made on first use; scene files cannot
    // name it.
    int interfaceMaterial() {
        if (interfaceMaterial_ < 0) {
            Material m;
            m.name = "(medium boundary)";
            m.interface = true;
            interfaceMaterial_ = int(scene_.materials.size());
            scene_.materials.push_back(m);
        }
        return interfaceMaterial_;
    }

    // ---- Shapes --------------------------------------------------------------------------

    void readShape(const json& value, const std::string& path) {
        if (!value.is_object()) fail(path, "an object", value);
        std::string type = text(required(value, path, "type", "mesh, sphere or quad"), keyPath(path, "type"));
        if (type == "sphere") {
            checkObject(value, path, {"type", "name", "material", "medium", "centre", "radius", "motion"});
            Sphere s;
            s.name = shapeName(value, path);
            s.medium = shapeMedium(value, path);
            s.material = shapeMaterial(value, path, s.medium);
            if (scene_.materials[s.material].emits())
                failInput(file_, keyPath(path, "material"),
                          "a non-emissive material (emitting spheres are not supported; use a mesh or an area light)",
                          "\"" + scene_.materials[s.material].name + "\" with emission");
            s.centre = point(required(value, path, "centre", "3 finite numbers"), keyPath(path, "centre"));
            s.radius = float(number(required(value, path, "radius", "a number > 0"), keyPath(path, "radius"), 0.0, 1e30,
                                    "a number > 0"));
            if (!(s.radius > 0)) fail(keyPath(path, "radius"), "a number > 0", value["radius"]);
            s.motion = motion(value, path);
            scene_.spheres.push_back(s);
        } else if (type == "quad") {
            checkObject(value, path, {"type", "name", "material", "medium", "corner", "edge_u", "edge_v", "motion"});
            TriangleMesh mesh = quadMesh(value, path);
            mesh.name = shapeName(value, path);
            mesh.medium = shapeMedium(value, path);  // refused by validateScene: a quad is not closed
            mesh.material = shapeMaterial(value, path, mesh.medium);
            mesh.motion = motion(value, path);
            scene_.meshes.push_back(std::move(mesh));
        } else if (type == "mesh") {
            if (value.contains("gltf")) {
                checkObject(value, path, {"type", "name", "material", "medium", "gltf", "transform", "motion"});
                readGltfMesh(value, path);
            } else {
                checkObject(value, path,
                            {"type", "name", "material", "medium", "positions", "indices", "normals", "uv", "transform",
                             "motion"});
                readInlineMesh(value, path);
            }
        } else {
            fail(keyPath(path, "type"), "one of mesh, sphere, quad", value["type"]);
        }
    }

    std::string shapeName(const json& value, const std::string& path) {
        auto* v = optional(value, "name");
        return v ? text(*v, keyPath(path, "name")) : path;
    }

    // corner, corner+u, corner+u+v, corner+v as two triangles (0,1,2), (0,2,3); both have the
    // geometric normal cross(u, v).
    TriangleMesh quadMesh(const json& value, const std::string& path) {
        Vec3 c = point(required(value, path, "corner", "3 finite numbers"), keyPath(path, "corner"));
        Vec3 u = point(required(value, path, "edge_u", "3 finite numbers"), keyPath(path, "edge_u"));
        Vec3 v = point(required(value, path, "edge_v", "3 finite numbers"), keyPath(path, "edge_v"));
        TriangleMesh mesh;
        mesh.positions = {c, c + u, c + u + v, c + v};
        mesh.indices = {0, 1, 2, 0, 2, 3};
        mesh.uv[0] = {0, 0, 1, 0, 1, 1, 0, 1};  // u along edge_u, v along edge_v: the whole image once
        return mesh;
    }

    void readInlineMesh(const json& value, const std::string& path) {
        TriangleMesh mesh;
        mesh.name = shapeName(value, path);
        mesh.medium = shapeMedium(value, path);
        mesh.material = shapeMaterial(value, path, mesh.medium);
        mesh.motion = motion(value, path);
        mesh.positions =
            vectors(required(value, path, "positions", "a flat array of 3N numbers"), keyPath(path, "positions"));
        if (mesh.positions.empty())
            fail(keyPath(path, "positions"), "a flat array of 3N numbers, N >= 3", value["positions"]);
        if (auto* n = optional(value, "normals")) {
            mesh.normals = vectors(*n, keyPath(path, "normals"));
            if (mesh.normals.size() != mesh.positions.size())
                failInput(file_, keyPath(path, "normals"),
                          std::to_string(mesh.positions.size() * 3) + " numbers (one normal per position)",
                          std::to_string(mesh.normals.size() * 3));
        }
        if (auto* t = optional(value, "uv")) {
            const std::string up = keyPath(path, "uv");
            const std::string expected = std::to_string(mesh.positions.size() * 2) +
                                         " finite numbers (u, v per position)";
            if (!t->is_array() || t->size() != mesh.positions.size() * 2) fail(up, expected, *t);
            for (size_t i = 0; i < t->size(); ++i)
                mesh.uv[0].push_back(float(number((*t)[i], indexPath(up, i), -1e30, 1e30, "a finite number")));
        }
        const json& idx = required(value, path, "indices", "a flat array of 3M vertex indices");
        std::string ip = keyPath(path, "indices");
        if (!idx.is_array() || idx.empty() || idx.size() % 3 != 0)
            fail(ip, "a flat array of 3M vertex indices, M >= 1", idx);
        mesh.indices.reserve(idx.size());
        for (size_t i = 0; i < idx.size(); ++i) {
            const json& k = idx[i];
            if (!k.is_number_integer() || k.get<int64_t>() < 0 || k.get<int64_t>() >= int64_t(mesh.positions.size()))
                fail(indexPath(ip, i),
                     "an integer vertex index in [0, " + std::to_string(mesh.positions.size() - 1) + "]", k);
            mesh.indices.push_back(uint32_t(k.get<int64_t>()));
        }
        if (auto* t = optional(value, "transform")) applyTransform(transform(*t, keyPath(path, "transform")), mesh);
        scene_.meshes.push_back(std::move(mesh));
    }

    std::vector<Vec3> vectors(const json& value, const std::string& path) {
        const std::string expected = "a flat array of 3N finite numbers";
        if (!value.is_array() || value.size() % 3 != 0) fail(path, expected, value);
        std::vector<Vec3> out(value.size() / 3);
        for (size_t i = 0; i < value.size(); ++i)
            out[i / 3][int(i % 3)] =
                float(number(value[i], indexPath(path, i), -kFloatMax, kFloatMax, "a finite number"));
        return out;
    }

    static void applyTransform(const Transform& t, TriangleMesh& mesh) {
        for (auto& p : mesh.positions) p = t.point(p);
        for (auto& n : mesh.normals) n = t.normal(n);
        if (t.flipsWinding())
            for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
    }

    // ---- glTF references -----------------------------------------------------------------

    std::string gltfPath(const json& value, const std::string& path) {
        std::string uri = text(value, path);
        std::string resolved = resolveInsideFolder(file_, path, uri);
        if (!endsWith(resolved, ".gltf") && !endsWith(resolved, ".glb"))
            failInput(file_, path, "a .gltf or .glb file", "\"" + uri + "\"");
#ifndef PHOTONCL_HAVE_GLTF
        failInput(file_, path,
                  "no glTF reference (this photoncl was built without glTF support, PHOTONCL_WITH_GLTF=OFF)",
                  "\"" + uri + "\"");
#endif
        return resolved;
    }

    void readGltfMesh(const json& value, const std::string& path) {
        std::string file = gltfPath(value["gltf"], keyPath(path, "gltf"));
#ifdef PHOTONCL_HAVE_GLTF
        GltfImportOptions options;
        options.geometryOnly = true;
        const int medium = shapeMedium(value, path);
        if (medium >= 0 || optional(value, "material")) options.materialOverride = shapeMaterial(value, path, medium);
        if (auto* t = optional(value, "transform")) options.transform = transform(*t, keyPath(path, "transform"));
        options.motion = motion(value, path);
        const size_t firstMesh = scene_.meshes.size();
        importGltf(scene_, file, options);
        for (size_t i = firstMesh; i < scene_.meshes.size(); ++i) scene_.meshes[i].medium = medium;
#endif
    }

    // "include": "x.gltf" | ["a.gltf", {"file": "b.glb", "transform": {...}}]
    void readIncludes(const json& value, const std::string& path) {
        if (value.is_string()) {
            readInclude(value, path, Transform());
        } else if (value.is_array()) {
            for (size_t i = 0; i < value.size(); ++i) {
                const json& item = value[i];
                std::string ip = indexPath(path, i);
                if (item.is_object()) {
                    checkObject(item, ip, {"file", "transform"});
                    Transform t;
                    if (auto* tv = optional(item, "transform")) t = transform(*tv, keyPath(ip, "transform"));
                    readInclude(required(item, ip, "file", "a .gltf or .glb file"), keyPath(ip, "file"), t);
                } else {
                    readInclude(item, ip, Transform());
                }
            }
        } else {
            fail(path, "a file name or an array of file names / {file, transform} objects", value);
        }
    }

    void readInclude(const json& value, const std::string& path, const Transform& t) {
        std::string file = gltfPath(value, path);
#ifdef PHOTONCL_HAVE_GLTF
        GltfImportOptions options;
        options.transform = t;
        GltfImportResult r = importGltf(scene_, file, options);
        if (r.hasCamera && !includedCamera_) includedCamera_ = r.camera;
#else
        (void)t;
#endif
    }

    // ---- Lights --------------------------------------------------------------------------

    // "power" (W) or "intensity" (W/sr), exactly one; returns the intensity. `solidAngle` is the
    // power-weighted solid angle of the emission profile, so I = Φ / solidAngle.
    Vec3 intensityOrPower(const json& value, const std::string& path, double solidAngle) {
        auto* power = optional(value, "power");
        auto* intensity = optional(value, "intensity");
        if ((power != nullptr) == (intensity != nullptr))
            failInput(file_, path, "exactly one of \"power\" (W) and \"intensity\" (W/sr)", power ? "both" : "neither");
        if (intensity) return lightAmount(*intensity, keyPath(path, "intensity"));
        return lightAmount(*power, keyPath(path, "power")) * float(1.0 / solidAngle);
    }

    void readLight(const json& value, const std::string& path) {
        if (!value.is_object()) fail(path, "an object", value);
        std::string type =
            text(required(value, path, "type", "point, spot, area or directional"), keyPath(path, "type"));
        Light light;
        auto* name = optional(value, "name");
        light.name = name ? text(*name, keyPath(path, "name")) : path;
        if (type == "point") {
            checkObject(value, path, {"type", "name", "position", "power", "intensity"});
            light.type = LightType::Point;
            light.position = point(required(value, path, "position", "3 finite numbers"), keyPath(path, "position"));
            light.intensity = intensityOrPower(value, path, 4.0 * kPiD);  // I = Φ / 4π
        } else if (type == "spot") {
            checkObject(value, path,
                        {"type", "name", "position", "direction", "power", "intensity", "inner_angle", "outer_angle"});
            light.type = LightType::Spot;
            light.position = point(required(value, path, "position", "3 finite numbers"), keyPath(path, "position"));
            light.direction = direction(required(value, path, "direction", "3 finite numbers, not all zero"),
                                        keyPath(path, "direction"));
            const std::string range = "a half-angle in degrees in (0, 90]";
            double outer =
                number(required(value, path, "outer_angle", range), keyPath(path, "outer_angle"), 0.0, 90.0, range);
            if (!(outer > 0)) fail(keyPath(path, "outer_angle"), range, value["outer_angle"]);
            double inner = 0.0;
            if (auto* v = optional(value, "inner_angle"))
                inner = number(*v, keyPath(path, "inner_angle"), 0.0, outer,
                               "a half-angle in degrees in [0, outer_angle = " + showJson(value["outer_angle"]) + "]");
            double cosInner = std::cos(inner * kPiD / 180.0), cosOuter = std::cos(outer * kPiD / 180.0);
            light.cosInner = float(cosInner);
            light.cosOuter = float(cosOuter);
            // Full intensity inside the inner cone, smoothstep in cosθ down to the outer cone,
            // whose integral over its cos range is half its width: Φ = I·2π·((1-ci) + (ci-co)/2).
            light.intensity =
                intensityOrPower(value, path, 2.0 * kPiD * ((1.0 - cosInner) + 0.5 * (cosInner - cosOuter)));
        } else if (type == "directional") {
            checkObject(value, path, {"type", "name", "direction", "irradiance"});
            light.type = LightType::Directional;
            light.direction = direction(required(value, path, "direction", "3 finite numbers, not all zero"),
                                        keyPath(path, "direction"));
            light.irradiance = lightAmount(required(value, path, "irradiance", "3 finite numbers >= 0, not all zero"),
                                           keyPath(path, "irradiance"));
        } else if (type == "area") {
            readAreaLight(value, path, light);
            return;
        } else {
            fail(keyPath(path, "type"), "one of point, spot, area, directional", value["type"]);
        }
        scene_.lights.push_back(light);
    }

    // An area light becomes a one-sided emissive TriangleMesh with its own black material, and a
    // Light{Area} pointing at it. Radiance from total power: Φ = π·A·L for a Lambertian emitter.
    void readAreaLight(const json& value, const std::string& path, Light& light) {
        auto* shapeValue = optional(value, "shape");
        std::string shape = shapeValue ? text(*shapeValue, keyPath(path, "shape")) : "";
        TriangleMesh mesh;
        if (shape == "quad") {
            checkObject(value, path, {"type", "name", "shape", "corner", "edge_u", "edge_v", "radiance", "power"});
            mesh = quadMesh(value, path);
        } else if (shape == "triangle") {
            checkObject(value, path, {"type", "name", "shape", "vertices", "radiance", "power"});
            const json& v = required(value, path, "vertices", "3 points [[x,y,z],[x,y,z],[x,y,z]]");
            if (!v.is_array() || v.size() != 3)
                fail(keyPath(path, "vertices"), "3 points [[x,y,z],[x,y,z],[x,y,z]]", v);
            for (size_t i = 0; i < 3; ++i)
                mesh.positions.push_back(point(v[i], indexPath(keyPath(path, "vertices"), i)));
            mesh.indices = {0, 1, 2};
        } else {
            fail(keyPath(path, "shape"), "quad or triangle", shapeValue ? *shapeValue : json("nothing"));
        }
        double area = 0;
        for (size_t i = 0; i < mesh.indices.size(); i += 3) {
            Vec3 p0 = mesh.positions[mesh.indices[i]];
            area += 0.5 * double(length(cross(mesh.positions[mesh.indices[i + 1]] - p0,
                                              mesh.positions[mesh.indices[i + 2]] - p0)));
        }
        if (!(area > 0) || !std::isfinite(area))
            failInput(file_, path, "a light shape of non-zero, finite area", "area " + std::to_string(area));

        auto* radiance = optional(value, "radiance");
        auto* power = optional(value, "power");
        if ((radiance != nullptr) == (power != nullptr))
            failInput(file_, path, "exactly one of \"radiance\" (W m^-2 sr^-1) and \"power\" (W)",
                      radiance ? "both" : "neither");
        Material emitter;
        emitter.name = light.name + ":emitter";
        emitter.emission = radiance ? lightAmount(*radiance, keyPath(path, "radiance"))
                                    : lightAmount(*power, keyPath(path, "power")) * float(1.0 / (kPiD * area));
        if (!isFinite(emitter.emission)) failInput(file_, path, "a finite radiance", "power / (pi * area) overflowing");

        mesh.name = light.name;
        mesh.material = int(scene_.materials.size());
        scene_.materials.push_back(emitter);
        light.type = LightType::Area;
        light.mesh = int(scene_.meshes.size());
        scene_.meshes.push_back(std::move(mesh));
        scene_.lights.push_back(light);
    }

    // ---- Camera --------------------------------------------------------------------------

    void readCamera(const json& value, const std::string& path) {
        checkObject(value, path,
                    {"type", "position", "look_at", "up", "fov", "resolution", "aperture_radius", "focus_distance",
                     "shutter"});
        Camera c;
        std::string type = "pinhole";
        if (auto* t = optional(value, "type")) type = text(*t, keyPath(path, "type"));
        if (type == "pinhole") {
            c.model = CameraModel::Pinhole;
            for (const char* key : {"aperture_radius", "focus_distance"})
                if (value.contains(key))
                    failInput(file_, keyPath(path, key),
                              "no lens settings for a pinhole camera (use \"type\": \"thin_lens\")",
                              showJson(value[key]));
        } else if (type == "thin_lens") {
            c.model = CameraModel::ThinLens;
        } else {
            fail(keyPath(path, "type"), "pinhole or thin_lens", value["type"]);
        }
        c.position = point(required(value, path, "position", "3 finite numbers"), keyPath(path, "position"));
        c.lookAt = point(required(value, path, "look_at", "3 finite numbers"), keyPath(path, "look_at"));
        Vec3 forward = c.lookAt - c.position;
        if (!(length(forward) > 0))
            fail(keyPath(path, "look_at"), "a point different from the camera position", value["look_at"]);
        if (auto* u = optional(value, "up")) c.up = direction(*u, keyPath(path, "up"));
        if (!(length(cross(normalize(forward), c.up)) > 1e-4f))
            fail(keyPath(path, "up"), "a direction not parallel to the viewing direction",
                 value.value("up", json({0, 1, 0})));
        c.vfovDegrees =
            float(number(required(value, path, "fov", "vertical field of view in degrees in (0, 180)"),
                         keyPath(path, "fov"), 0.0, 180.0, "vertical field of view in degrees in (0, 180)"));
        if (!(c.vfovDegrees > 0 && c.vfovDegrees < 180))
            fail(keyPath(path, "fov"), "vertical field of view in degrees in (0, 180)", value["fov"]);
        if (auto* r = optional(value, "resolution")) {
            const std::string expected = "2 integers [width, height], each in [1, 16384]";
            if (!r->is_array() || r->size() != 2) fail(keyPath(path, "resolution"), expected, *r);
            for (int i = 0; i < 2; ++i)
                if (!(*r)[i].is_number_integer() || (*r)[i].get<int64_t>() < 1 || (*r)[i].get<int64_t>() > 16384)
                    fail(keyPath(path, "resolution"), expected, *r);
            c.width = int((*r)[0].get<int64_t>());
            c.height = int((*r)[1].get<int64_t>());
        }
        if (c.model == CameraModel::ThinLens) {
            c.apertureRadius = float(number(required(value, path, "aperture_radius", "a lens radius > 0"),
                                            keyPath(path, "aperture_radius"), 0.0, kFloatMax, "a lens radius > 0"));
            if (!(c.apertureRadius > 0))
                fail(keyPath(path, "aperture_radius"), "a lens radius > 0", value["aperture_radius"]);
            c.focusDistance = length(forward);
            if (auto* f = optional(value, "focus_distance")) {
                c.focusDistance = float(number(*f, keyPath(path, "focus_distance"), 0.0, kFloatMax, "a distance > 0"));
                if (!(c.focusDistance > 0)) fail(keyPath(path, "focus_distance"), "a distance > 0", *f);
            }
        }
        if (auto* s = optional(value, "shutter")) {
            const std::string expected = "[open, close] in seconds with 0 <= open <= close";
            Vec3 t;
            if (!s->is_array() || s->size() != 2) fail(keyPath(path, "shutter"), expected, *s);
            for (int i = 0; i < 2; ++i) t[i] = float(number((*s)[i], keyPath(path, "shutter"), 0.0, 1e6, expected));
            if (t.x > t.y) fail(keyPath(path, "shutter"), expected, *s);
            c.shutterOpen = t.x;
            c.shutterClose = t.y;
        }
        scene_.camera = c;
    }

    std::string file_;
    Scene scene_;
    std::map<std::string, int> materialIndex_;
    std::map<std::string, int> mediumIndex_;
    int interfaceMaterial_ = -1;  // the shared invisible-boundary material, once a shape needs it
    std::optional<Camera> includedCamera_;
};

}  // namespace

Scene parseJsonScene(const std::string& text, const std::string& path) {
    json root = parseSceneJson(text, path);
    return JsonSceneReader(path).read(root);
}

Scene loadJsonScene(const std::string& path) { return parseJsonScene(readTextFile(path), path); }

}  // namespace pcl
