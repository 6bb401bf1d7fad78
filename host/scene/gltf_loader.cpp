// glTF 2.0 → Scene through tinygltf. Before tinygltf sees a file, it is parsed once more here
// (nesting limit, asset version, required extensions, buffer URIs kept inside the scene folder)
// and parts this renderer never uses (images, textures, animations, skins) are cut out, so
// neither stb_image nor tinygltf's less-travelled paths run on untrusted bytes. Every accessor
// is bounds-checked here before it is read.
//
// The mapping to photoncl materials and lights is documented in scenes/README.md.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include "scene/gltf_loader.h"
#include "core/math.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <tiny_gltf.h>

#include "scene/json_parse.h"
#include "scene/scene_error.h"
#include "scene/scene_paths.h"
#include "scene/texture_image.h"

namespace pcl {

namespace {

using json = nlohmann::json;
// Photometric → radiometric: 683 lm/W, the luminous efficacy at 555 nm (the definition of the
// candela). glTF punctual lights are in candela (point, spot) and lux (directional).
constexpr double kLumensPerWatt = 683.0;

const char* const kSupportedExtensions[] = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                            "KHR_materials_transmission", "KHR_materials_ior", "KHR_texture_transform"};

std::string at(const std::string& what, size_t i) { return what + "[" + std::to_string(i) + "]"; }

// ---- The GLB container (binary glTF): header, JSON chunk, optional BIN chunk -------------------

constexpr uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

uint32_t readU32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
void writeU32(std::vector<unsigned char>& out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
}

struct GlbParts {
    std::string json;
    std::vector<unsigned char> bin;
    bool hasBin = false;
};

GlbParts splitGlb(const std::vector<unsigned char>& bytes, const std::string& file) {
    const std::string expected = "a GLB container (12-byte header, JSON chunk, optional BIN chunk)";
    if (bytes.size() < 20) failInput(file, "", expected, std::to_string(bytes.size()) + " bytes");
    uint32_t version = readU32(&bytes[4]);
    uint64_t length = readU32(&bytes[8]);
    if (version != 2) failInput(file, "header.version", "2", std::to_string(version));
    if (length > bytes.size())
        failInput(file, "header.length", "at most the file size " + std::to_string(bytes.size()),
                  std::to_string(length));
    GlbParts parts;
    uint64_t offset = 12;
    for (int chunk = 0; offset + 8 <= length; ++chunk) {
        uint64_t size = readU32(&bytes[offset]);
        uint32_t type = readU32(&bytes[offset + 4]);
        if (offset + 8 + size > length)
            failInput(file, at("chunks", size_t(chunk)), "a chunk inside the file", "one running past its end");
        const unsigned char* data = &bytes[offset + 8];
        if (chunk == 0) {
            if (type != kChunkJson) failInput(file, "chunks[0]", "the JSON chunk first", "another chunk type");
            parts.json.assign(reinterpret_cast<const char*>(data), size);
        } else if (chunk == 1 && type == kChunkBin) {
            parts.bin.assign(data, data + size);
            parts.hasBin = true;
        }
        offset += 8 + ((size + 3) & ~uint64_t(3));  // chunks are 4-byte aligned
    }
    if (parts.json.empty()) failInput(file, "chunks[0]", "a JSON chunk", "none");
    return parts;
}

std::vector<unsigned char> joinGlb(const std::string& jsonText, const GlbParts& parts) {
    std::string text = jsonText;
    while (text.size() % 4) text += ' ';
    std::vector<unsigned char> out;
    uint64_t total = 12 + 8 + text.size() + (parts.hasBin ? 8 + ((parts.bin.size() + 3) & ~size_t(3)) : 0);
    writeU32(out, kGlbMagic);
    writeU32(out, 2);
    writeU32(out, uint32_t(total));
    writeU32(out, uint32_t(text.size()));
    writeU32(out, kChunkJson);
    out.insert(out.end(), text.begin(), text.end());
    if (parts.hasBin) {
        writeU32(out, uint32_t((parts.bin.size() + 3) & ~size_t(3)));
        writeU32(out, kChunkBin);
        out.insert(out.end(), parts.bin.begin(), parts.bin.end());
        while (out.size() % 4) out.push_back(0);
    }
    return out;
}

// ---- The check before tinygltf -----------------------------------------------------------------

void preflight(json& root, const std::string& file, bool binary) {
    if (!root.is_object()) failInput(file, "", "a JSON object at the top level", showJson(root));
    auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object() || !asset->contains("version") || !(*asset)["version"].is_string())
        failInput(file, "asset.version", "\"2.0\"", asset == root.end() ? "nothing" : showJson(*asset));
    std::string version = (*asset)["version"].get<std::string>();
    if (version.rfind("2.", 0) != 0) failInput(file, "asset.version", "\"2.0\"", "\"" + version + "\"");

    if (auto req = root.find("extensionsRequired"); req != root.end()) {
        if (!req->is_array()) failInput(file, "extensionsRequired", "an array of extension names", showJson(*req));
        for (size_t i = 0; i < req->size(); ++i) {
            const json& e = (*req)[i];
            bool ok = e.is_string();
            if (ok) {
                ok = false;
                for (const char* s : kSupportedExtensions) ok = ok || e.get<std::string>() == s;
            }
            if (!ok) {
                std::string list;
                for (const char* s : kSupportedExtensions) list += (list.empty() ? "" : ", ") + std::string(s);
                failInput(file, at("extensionsRequired", i), "a supported extension (" + list + ")",
                          "unsupported " + showJson(e));
            }
        }
    }

    if (auto buffers = root.find("buffers"); buffers != root.end() && buffers->is_array()) {
        for (size_t i = 0; i < buffers->size(); ++i) {
            const json& b = (*buffers)[i];
            std::string field = at("buffers", i) + ".uri";
            if (!b.is_object()) failInput(file, at("buffers", i), "an object", showJson(b));
            auto uri = b.find("uri");
            if (uri == b.end()) {
                if (!(binary && i == 0))
                    failInput(file, field, "a buffer URI (only a .glb's first buffer may omit it)", "none");
                continue;
            }
            if (!uri->is_string()) failInput(file, field, "a string", showJson(*uri));
            std::string u = uri->get<std::string>();
            if (u.rfind("data:", 0) == 0) continue;
            std::string path = resolveInsideFolder(file, field, percentDecode(u));
            if (!std::ifstream(path, std::ios::binary))
                failInput(file, field, "an existing buffer file next to the scene",
                          "\"" + u + "\" (missing: " + path + ")");
        }
    }

    // Images, textures and samplers are read here (GltfTextures, from the JSON kept aside), not by
    // tinygltf, which would decode images with stb_image; animation is not used. Cut them out.
    for (const char* unused : {"images", "textures", "samplers", "animations", "skins"}) root.erase(unused);
}

// What the loader reads of a file's textures itself: the arrays preflight cuts out, and each
// material's texture references (scenes/README.md, "glTF: textures").
struct GltfTextures {
    json images = json::array(), textures = json::array(), samplers = json::array(), materials = json::array();
    explicit GltfTextures(const json& root) {
        for (auto [key, out] : {std::make_pair("images", &images), std::make_pair("textures", &textures),
                                std::make_pair("samplers", &samplers), std::make_pair("materials", &materials)}) {
            auto it = root.find(key);
            if (it != root.end() && it->is_array()) *out = *it;
        }
    }
};

// tinygltf reads files through these, so a path it builds (including its "./" fallback that
// would search the working directory) is refused unless it lies in the scene's folder.
struct FsContext {
    std::string folder;
};
bool fsFileExists(const std::string& path, void* user) {
    return isInsideFolder(static_cast<FsContext*>(user)->folder, path) && tinygltf::FileExists(path, nullptr);
}
std::string fsExpandFilePath(const std::string& path, void*) { return path; }
bool fsReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    if (!isInsideFolder(static_cast<FsContext*>(user)->folder, path)) {
        if (err) *err += path + " is outside the scene's folder";
        return false;
    }
    return tinygltf::ReadWholeFile(out, err, path, nullptr);
}
bool fsWriteWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not allowed";
    return false;
}
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;
}

// ---- Reading the model -----------------------------------------------------------------------

class GltfReader {
public:
    GltfReader(Scene& scene, const tinygltf::Model& model, const std::string& file, const GltfImportOptions& options,
               const GltfTextures& textures)
        : scene_(scene), model_(model), file_(file), options_(options), textures_(textures) {}

    GltfImportResult read() {
        materialIndex_.assign(model_.materials.size(), -1);
        walkNodes();
        if (!ignoredTextures_.empty())
            warnInput(file_,
                      "textures ignored: " + ignoredTextures_ +
                          " (only baseColorTexture, metallicRoughnessTexture, normalTexture and emissiveTexture from "
                          "image files "
                          "are read; materials use their factors)");
        return result_;
    }

private:
    [[noreturn]] void fail(const std::string& field, const std::string& expected, const std::string& got) {
        failInput(file_, field, expected, got);
    }

    // ---- Node hierarchy: iterative depth-first, parents before children, in file order.
    void walkNodes() {
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (size_t(s) >= model_.scenes.size())
                fail("scene", "a scene index below " + std::to_string(model_.scenes.size()), std::to_string(s));
            roots = model_.scenes[size_t(s)].nodes;
        } else {
            std::vector<bool> isChild(model_.nodes.size(), false);
            for (const auto& n : model_.nodes)
                for (int c : n.children)
                    if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = true;
            for (size_t i = 0; i < model_.nodes.size(); ++i)
                if (!isChild[i]) roots.push_back(int(i));
        }
        std::vector<bool> visited(model_.nodes.size(), false);
        std::vector<std::pair<int, Transform>> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, options_.transform});
        while (!stack.empty()) {
            auto [index, parent] = stack.back();
            stack.pop_back();
            if (index < 0 || size_t(index) >= model_.nodes.size())
                fail("nodes", "node indices below " + std::to_string(model_.nodes.size()), std::to_string(index));
            if (visited[size_t(index)])
                fail(at("nodes", size_t(index)), "each node once in the hierarchy (glTF nodes form a tree)",
                     "a node reached twice (a cycle or a shared child)");
            visited[size_t(index)] = true;
            const tinygltf::Node& node = model_.nodes[size_t(index)];
            Transform world = parent * localTransform(node, at("nodes", size_t(index)));
            if (present(node.mesh, at("nodes", size_t(index)) + ".mesh")) addMesh(node.mesh, world);
            if (!options_.geometryOnly) {
                if (present(node.camera, at("nodes", size_t(index)) + ".camera") && !result_.hasCamera)
                    readCamera(node.camera, world);
                auto light = node.extensions.find("KHR_lights_punctual");
                if (light != node.extensions.end()) addLight(light->second, world, at("nodes", size_t(index)));
            }
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world});
        }
    }

    // tinygltf stores an absent index as -1 and any other negative number as written: that one is
    // bad input, not "absent" (it would drop a mesh's indices or a node's mesh without a word).
    bool present(int index, const std::string& field) {
        if (index < -1) fail(field, "an index >= 0", std::to_string(index));
        return index >= 0;
    }

    Transform localTransform(const tinygltf::Node& node, const std::string& field) {
        auto finite = [&](const std::vector<double>& v, size_t n, const char* name) {
            if (v.empty()) return false;
            if (v.size() != n)
                fail(field + "." + name, std::to_string(n) + " numbers", std::to_string(v.size()) + " numbers");
            for (double x : v)
                if (!std::isfinite(x)) fail(field + "." + name, "finite numbers", "a non-finite one");
            return true;
        };
        Transform t;
        if (finite(node.matrix, 16, "matrix")) {
            // Column-major: the last row is elements 3, 7, 11, 15. A projective row would make
            // the transform non-affine, which nothing downstream can represent.
            const std::vector<double>& m = node.matrix;
            if (m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0) {
                std::ostringstream row;
                row << "last row " << m[3] << " " << m[7] << " " << m[11] << " " << m[15];
                const std::string name = node.name.empty() ? "" : " (\"" + node.name + "\")";
                fail(field + name + ".matrix",
                     "an affine matrix (column-major: elements 3, 7, 11 equal to 0 and 15 to 1, last row 0 0 0 1)",
                     row.str());
            }
            t = Transform::columnMajor(m.data());
        } else {
            Transform tr, r, s;
            if (finite(node.translation, 3, "translation"))
                tr = Transform::translate(node.translation[0], node.translation[1], node.translation[2]);
            if (finite(node.rotation, 4, "rotation"))
                r = Transform::quaternion(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]);
            if (finite(node.scale, 3, "scale")) s = Transform::scale(node.scale[0], node.scale[1], node.scale[2]);
            t = tr * r * s;
        }
        if (!t.isFinite()) fail(field, "a finite transform", "a non-finite one");
        return t;
    }

    // ---- Accessors: every byte range is checked against its bufferView and buffer.
    struct View {
        const unsigned char* data = nullptr;
        size_t count = 0, stride = 0;
        int componentType = 0;
    };

    View view(int index, const std::string& field, int type, std::initializer_list<int> componentTypes) {
        if (index < 0 || size_t(index) >= model_.accessors.size())
            fail(field, "an accessor index below " + std::to_string(model_.accessors.size()), std::to_string(index));
        const tinygltf::Accessor& a = model_.accessors[size_t(index)];
        std::string af = at("accessors", size_t(index));
        if (a.sparse.isSparse)
            fail(af + ".sparse", "a dense accessor (sparse accessors are not supported)", "a sparse one");
        if (a.type != type)
            fail(af + ".type",
                 type == TINYGLTF_TYPE_VEC4   ? "VEC4"
                 : type == TINYGLTF_TYPE_VEC3 ? "VEC3"
                 : type == TINYGLTF_TYPE_VEC2 ? "VEC2"
                                              : "SCALAR",
                 "type code " + std::to_string(a.type));
        bool allowed = false;
        for (int c : componentTypes) allowed = allowed || a.componentType == c;
        if (!allowed)
            fail(af + ".componentType",
                 type == TINYGLTF_TYPE_VEC3 ? "FLOAT (5126)"
                 : type == TINYGLTF_TYPE_VEC2
                     ? "FLOAT (5126), or normalized UNSIGNED_BYTE (5121) or UNSIGNED_SHORT (5123)"
                     : "UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                 std::to_string(a.componentType));
        View v;
        v.componentType = a.componentType;
        v.count = a.count;
        if (a.count == 0) return v;
        if (a.bufferView < 0 || size_t(a.bufferView) >= model_.bufferViews.size())
            fail(af + ".bufferView", "a bufferView index below " + std::to_string(model_.bufferViews.size()),
                 std::to_string(a.bufferView));
        const tinygltf::BufferView& bv = model_.bufferViews[size_t(a.bufferView)];
        std::string bvf = at("bufferViews", size_t(a.bufferView));
        if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
            fail(bvf + ".buffer", "a buffer index below " + std::to_string(model_.buffers.size()),
                 std::to_string(bv.buffer));
        const tinygltf::Buffer& buffer = model_.buffers[size_t(bv.buffer)];
        uint64_t componentSize = uint64_t(tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)));
        uint64_t elementSize = componentSize * uint64_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
        uint64_t stride = bv.byteStride ? uint64_t(bv.byteStride) : elementSize;
        if (stride < elementSize || stride > 252)
            fail(bvf + ".byteStride", "0 or a stride in [" + std::to_string(elementSize) + ", 252]",
                 std::to_string(bv.byteStride));
        if (uint64_t(bv.byteOffset) > buffer.data.size() ||
            uint64_t(bv.byteLength) > buffer.data.size() - bv.byteOffset)
            fail(bvf,
                 "a byte range inside buffer " + std::to_string(bv.buffer) + " (" + std::to_string(buffer.data.size()) +
                     " bytes)",
                 "offset " + std::to_string(bv.byteOffset) + " + length " + std::to_string(bv.byteLength));
        // count is bounded first so the multiplication below cannot overflow.
        if (uint64_t(a.count) > bv.byteLength || uint64_t(a.byteOffset) > bv.byteLength ||
            uint64_t(a.byteOffset) + (uint64_t(a.count) - 1) * stride + elementSize > bv.byteLength)
            fail(af,
                 "elements inside bufferView " + std::to_string(a.bufferView) + " (" + std::to_string(bv.byteLength) +
                     " bytes)",
                 std::to_string(a.count) + " elements of " + std::to_string(elementSize) + " bytes at offset " +
                     std::to_string(a.byteOffset) + ", stride " + std::to_string(stride));
        v.data = buffer.data.data() + bv.byteOffset + a.byteOffset;
        v.stride = size_t(stride);
        return v;
    }

    std::vector<Vec3> readVec3(int index, const std::string& field) {
        View v = view(index, field, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT});
        std::vector<Vec3> out(v.count);
        for (size_t i = 0; i < v.count; ++i) std::memcpy(&out[i], v.data + i * v.stride, sizeof(float) * 3);
        return out;
    }

    // TANGENT: x, y, z, w per vertex, VEC4 of FLOAT (glTF 2.0 §3.7.2.1), finite, w = ±1.
    std::vector<float> readTangents(int index, const std::string& field) {
        View v = view(index, field, TINYGLTF_TYPE_VEC4, {TINYGLTF_COMPONENT_TYPE_FLOAT});
        std::vector<float> out(4 * v.count);
        for (size_t i = 0; i < v.count; ++i) std::memcpy(&out[4 * i], v.data + i * v.stride, sizeof(float) * 4);
        for (size_t i = 0; i < v.count; ++i) {
            for (int c = 0; c < 4; ++c)
                if (!std::isfinite(out[4 * i + size_t(c)]))
                    fail(field, "finite tangents", show(out[4 * i + size_t(c)]));
            if (out[4 * i + 3] != 1.0f && out[4 * i + 3] != -1.0f)
                fail(field, "w = 1 or -1 (the bitangent's sign)", show(out[4 * i + 3]));
        }
        return out;
    }

    // TEXCOORD_n: (u, v) per vertex, FLOAT or normalized unsigned integers (glTF 2.0 §3.7.2.1).
    std::vector<float> readTexCoords(int index, const std::string& field) {
        View v = view(index, field, TINYGLTF_TYPE_VEC2,
                      {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT});
        const tinygltf::Accessor& a = model_.accessors[size_t(index)];
        if (v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized)
            fail(at("accessors", size_t(index)) + ".normalized", "true for integer texture coordinates", "false");
        std::vector<float> out(2 * v.count);
        for (size_t i = 0; i < v.count; ++i) {
            const unsigned char* p = v.data + i * v.stride;
            for (int c = 0; c < 2; ++c) {
                if (v.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                    std::memcpy(&out[2 * i + size_t(c)], p + 4 * c, 4);
                    if (!std::isfinite(out[2 * i + size_t(c)]))
                        fail(field, "finite texture coordinates", show(out[2 * i + size_t(c)]));
                } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                    out[2 * i + size_t(c)] = float(p[c]) / 255.0f;
                } else {
                    uint16_t s;
                    std::memcpy(&s, p + 2 * c, 2);
                    out[2 * i + size_t(c)] = float(s) / 65535.0f;
                }
            }
        }
        return out;
    }

    std::vector<uint32_t> readIndices(int index, const std::string& field) {
        View v = view(index, field, TINYGLTF_TYPE_SCALAR,
                      {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
        std::vector<uint32_t> out(v.count);
        for (size_t i = 0; i < v.count; ++i) {
            const unsigned char* p = v.data + i * v.stride;
            if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                out[i] = p[0];
            } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                uint16_t s;
                std::memcpy(&s, p, 2);
                out[i] = s;
            } else {
                std::memcpy(&out[i], p, 4);
            }
        }
        return out;
    }

    // ---- Meshes
    void addMesh(int meshIndex, const Transform& world) {
        if (size_t(meshIndex) >= model_.meshes.size())
            fail("nodes[].mesh", "a mesh index below " + std::to_string(model_.meshes.size()),
                 std::to_string(meshIndex));
        const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = mesh.primitives[p];
            std::string field = at("meshes", size_t(meshIndex)) + "." + at("primitives", p);
            int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                warnInput(file_, field + ": points and lines are skipped (mode " + std::to_string(mode) + ")");
                continue;
            }
            auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) fail(field + ".attributes.POSITION", "a POSITION accessor", "none");
            TriangleMesh out;
            out.name = file_ + ":" + (mesh.name.empty() ? at("meshes", size_t(meshIndex)) : mesh.name) + "/" +
                       std::to_string(p);
            out.positions = readVec3(pos->second, field + ".attributes.POSITION");
            auto nrm = prim.attributes.find("NORMAL");
            if (nrm != prim.attributes.end()) {
                out.normals = readVec3(nrm->second, field + ".attributes.NORMAL");
                if (out.normals.size() != out.positions.size())
                    fail(field + ".attributes.NORMAL",
                         std::to_string(out.positions.size()) + " normals (one per position)",
                         std::to_string(out.normals.size()));
            }
            if (auto tan = prim.attributes.find("TANGENT"); tan != prim.attributes.end()) {
                out.tangents = readTangents(tan->second, field + ".attributes.TANGENT");
                if (out.tangents.size() != 4 * out.positions.size())
                    fail(field + ".attributes.TANGENT",
                         std::to_string(out.positions.size()) + " tangents (one per position)",
                         std::to_string(out.tangents.size() / 4));
            }
            for (int set = 0; set < 2; ++set) {
                const std::string name = "TEXCOORD_" + std::to_string(set);
                auto tc = prim.attributes.find(name);
                if (tc == prim.attributes.end()) continue;
                out.uv[set] = readTexCoords(tc->second, field + ".attributes." + name);
                if (out.uv[set].size() != 2 * out.positions.size())
                    fail(field + ".attributes." + name,
                         std::to_string(out.positions.size()) + " coordinates (one per position)",
                         std::to_string(out.uv[set].size() / 2));
            }
            std::vector<uint32_t> vertices;
            if (present(prim.indices, field + ".indices")) {
                vertices = readIndices(prim.indices, field + ".indices");
                for (uint32_t k : vertices)
                    if (k >= out.positions.size())
                        fail(field + ".indices", "vertex indices below " + std::to_string(out.positions.size()),
                             std::to_string(k));
            } else {
                vertices.resize(out.positions.size());
                for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = uint32_t(i);
            }
            out.indices = triangles(vertices, mode);
            for (auto& x : out.positions) x = world.point(x);
            for (auto& n : out.normals) n = world.normal(n);
            for (size_t v = 0; 4 * v < out.tangents.size(); ++v) {
                // A tangent is a surface direction (the linear part moves it); a mirroring
                // transform flips the handedness of (N, T, B), so w changes sign.
                const Vec3 t =
                    world.vector(Vec3(out.tangents[4 * v], out.tangents[4 * v + 1], out.tangents[4 * v + 2]));
                const float l = length(t);
                const Vec3 u = l > 0.0f ? t / l : Vec3(0.0f);
                out.tangents[4 * v] = u.x;
                out.tangents[4 * v + 1] = u.y;
                out.tangents[4 * v + 2] = u.z;
                if (world.flipsWinding()) out.tangents[4 * v + 3] = -out.tangents[4 * v + 3];
            }
            if (world.flipsWinding())
                for (size_t i = 0; i + 2 < out.indices.size(); i += 3)
                    std::swap(out.indices[i + 1], out.indices[i + 2]);
            present(prim.material, field + ".material");
            out.material = materialFor(prim.material, field + ".material");
            out.motion = options_.motion;
            if (out.indices.empty()) continue;
            scene_.meshes.push_back(std::move(out));
            ++result_.meshCount;
        }
    }

    static std::vector<uint32_t> triangles(const std::vector<uint32_t>& v, int mode) {
        std::vector<uint32_t> t;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            t.assign(v.begin(), v.begin() + long(v.size() / 3 * 3));
        } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            for (size_t i = 2; i < v.size(); ++i) {  // every other triangle is reversed to keep the winding
                if (i % 2 == 0) t.insert(t.end(), {v[i - 2], v[i - 1], v[i]});
                else t.insert(t.end(), {v[i - 1], v[i - 2], v[i]});
            }
        } else {
            for (size_t i = 2; i < v.size(); ++i) t.insert(t.end(), {v[0], v[i - 1], v[i]});
        }
        return t;
    }

    // ---- Materials: glTF metallic-roughness → ρd, ρs and a specular kind (scenes/README.md).
    int materialFor(int gltfIndex, const std::string& field) {
        if (options_.materialOverride >= 0) return options_.materialOverride;
        if (gltfIndex < 0) {
            if (defaultMaterial_ < 0) {
                Material m;
                m.name = file_ + ":default";
                m.rhoD = Vec3(0.8f);
                defaultMaterial_ = int(scene_.materials.size());
                scene_.materials.push_back(m);
            }
            return defaultMaterial_;
        }
        if (size_t(gltfIndex) >= model_.materials.size())
            fail(field, "a material index below " + std::to_string(model_.materials.size()), std::to_string(gltfIndex));
        int& mapped = materialIndex_[size_t(gltfIndex)];
        if (mapped < 0) {
            mapped = int(scene_.materials.size());
            Material m = mapMaterial(model_.materials[size_t(gltfIndex)], at("materials", size_t(gltfIndex)));
            mapTextures(size_t(gltfIndex), model_.materials[size_t(gltfIndex)], m);
            scene_.materials.push_back(m);
        }
        return mapped;
    }

    double factor(double x, const std::string& field, double lo, double hi) {
        if (!std::isfinite(x) || x < lo || x > hi)
            fail(field, "a number in [" + show(lo) + ", " + show(hi) + "]", show(x));
        return x;
    }
    static std::string show(double x) {
        std::ostringstream s;
        s << x;
        return s.str();
    }
    Vec3 color(const std::vector<double>& v, size_t n, const std::string& field, double hi) {
        if (v.size() != n) fail(field, std::to_string(n) + " numbers", std::to_string(v.size()) + " numbers");
        Vec3 c;
        for (int i = 0; i < 3; ++i) c[i] = float(factor(v[size_t(i)], field, 0.0, hi));
        return c;
    }
    double extensionNumber(const tinygltf::Material& m, const char* ext, const char* key, double fallback,
                           const std::string& field, double lo, double hi) {
        auto it = m.extensions.find(ext);
        if (it == m.extensions.end() || !it->second.IsObject() || !it->second.Has(key)) return fallback;
        const tinygltf::Value& v = it->second.Get(key);
        std::string f = field + ".extensions." + ext + "." + key;
        if (!v.IsNumber()) fail(f, "a number", "another type");
        return factor(v.GetNumberAsDouble(), f, lo, hi);
    }

    Material mapMaterial(const tinygltf::Material& g, const std::string& field) {
        const auto& pbr = g.pbrMetallicRoughness;
        std::string pf = field + ".pbrMetallicRoughness";
        Vec3 base = color(pbr.baseColorFactor, 4, pf + ".baseColorFactor", 1.0);
        double metallic = factor(pbr.metallicFactor, pf + ".metallicFactor", 0, 1);
        double roughness = factor(pbr.roughnessFactor, pf + ".roughnessFactor", 0, 1);
        Vec3 emissive = g.emissiveFactor.empty() ? Vec3(0.0f)
                                                 : color(g.emissiveFactor, 3, field + ".emissiveFactor", 1e30);
        double strength =
            extensionNumber(g, "KHR_materials_emissive_strength", "emissiveStrength", 1.0, field, 0, 1e30);
        double transmission = extensionNumber(g, "KHR_materials_transmission", "transmissionFactor", 0.0, field, 0, 1);
        double ior = extensionNumber(g, "KHR_materials_ior", "ior", 1.5, field, 1.0, 10.0);

        Material m;
        m.name = file_ + ":" + (g.name.empty() ? field : g.name);
        m.emission = emissive * float(strength);
        float t = float(transmission), k = float(metallic);
        if (t > 0) {
            // Transmissive: a dielectric carrying the transmitted share, the rest diffuse.
            m.specular = SpecularKind::Dielectric;
            m.ior = float(ior);
            m.rhoS = base * t;
            m.rhoD = base * ((1 - t) * (1 - k));
        } else {
            // Metal reflects its base colour; a dielectric coat reflects F0 = ((n-1)/(n+1))² and
            // leaves the rest to the diffuse base.
            float f0 = float(((ior - 1) / (ior + 1)) * ((ior - 1) / (ior + 1)));
            m.rhoS = base * k + Vec3((1 - k) * f0);
            m.rhoD = base * ((1 - k) * (1 - f0));
            // GGX α = roughness²; Blinn-Phong exponent 2/α² - 2 (Walter et al. 2007), and a lobe
            // around the mirror direction is about 4x narrower in angle: n_phong ≈ 1/(2α²) - 1/2.
            double alpha = roughness * roughness;
            double n = alpha > 0 ? 0.5 / (alpha * alpha) - 0.5 : 1e30;
            if (n >= 1e4) {
                m.specular = SpecularKind::Mirror;
            } else if (n < 1) {
                m.rhoD += m.rhoS;  // so rough that the lobe is about as wide as a diffuse one
                m.rhoS = Vec3(0.0f);
            } else {
                m.specular = SpecularKind::Glossy;
                m.phongExponent = float(n);
            }
        }
        float sum = maxComponent(m.rhoD + m.rhoS);
        if (sum > 1) {
            m.rhoD = m.rhoD / sum;
            m.rhoS = m.rhoS / sum;
        }
        return m;
    }

    // ---- Textures (scenes/README.md, "glTF: textures")

    // Without a metallicRoughnessTexture, a material's baseColorTexture multiplies its ρd (the
    // factor-derived constant). With one (an opaque material), the metallic-roughness mapping
    // runs per texel (kernels/shared/texture.h, texture_metallic_roughness): base colour =
    // factor × baseColorTexture, metallic = factor × B, roughness = factor × G, and the material
    // is glossy unless its factors make it a mirror (a texel is never rougher than the factor, so
    // a mirror stays one everywhere). An emissiveTexture multiplies the emission (emissiveFactor ×
    // strength). The other texture kinds are noted as ignored.
    void mapTextures(size_t gltfIndex, const tinygltf::Material& gm, Material& m) {
        if (gltfIndex >= textures_.materials.size() || !textures_.materials[gltfIndex].is_object()) return;
        const json& g = textures_.materials[gltfIndex];
        const std::string field = at("materials", gltfIndex);
        if (g.contains("occlusionTexture")) noteIgnored("occlusionTexture");
        if (auto emissive = g.find("emissiveTexture"); emissive != g.end()) {
            // glTF 2.0 §3.9.5: emitted = emissiveFactor × the texture (sRGB), here also × the
            // emissive strength (m.emission holds the product). With a zero factor it emits nothing.
            if (m.emits()) m.emissionTexture = textureFor(*emissive, field + ".emissiveTexture", TextureEncoding::Srgb);
            else noteIgnored("emissiveTexture of a material with emissiveFactor 0");
        }
        if (auto normal = g.find("normalTexture"); normal != g.end()) {
            // Linear texels (glTF 2.0 §3.9.3); scale multiplies the decoded x and y.
            const std::string nf = field + ".normalTexture";
            m.normalTexture = textureFor(*normal, nf, TextureEncoding::Linear);
            if (normal->is_object())
                if (auto s = normal->find("scale"); s != normal->end()) {
                    if (!s->is_number() || !std::isfinite(s->get<double>()))
                        fail(nf + ".scale", "a number", showJson(*s));
                    m.normalScale = float(s->get<double>());
                }
        }
        auto pbr = g.find("pbrMetallicRoughness");
        if (pbr == g.end() || !pbr->is_object()) return;
        const std::string pf = field + ".pbrMetallicRoughness";
        if (auto base = pbr->find("baseColorTexture"); base != pbr->end())
            m.rhoDTexture = textureFor(*base, pf + ".baseColorTexture", TextureEncoding::Srgb);
        auto mr = pbr->find("metallicRoughnessTexture");
        if (mr == pbr->end()) return;
        if (m.specular == SpecularKind::Dielectric) {
            noteIgnored("metallicRoughnessTexture of a transmissive material");
            return;
        }
        m.exponentTexture = textureFor(*mr, pf + ".metallicRoughnessTexture", TextureEncoding::Linear);
        if (m.exponentTexture < 0) return;
        Material::MetallicRoughness& f = m.metallicRoughness;
        f.active = true;
        f.baseColor = Vec3(float(gm.pbrMetallicRoughness.baseColorFactor[0]),
                           float(gm.pbrMetallicRoughness.baseColorFactor[1]),
                           float(gm.pbrMetallicRoughness.baseColorFactor[2]));
        f.metallic = float(gm.pbrMetallicRoughness.metallicFactor);
        f.roughness = float(gm.pbrMetallicRoughness.roughnessFactor);
        f.f0 = f0Of(gm, field);
        if (m.specular == SpecularKind::Mirror) return;
        // Glossy as a whole; the constants are the unfolded mapping of the factors (each hit
        // replaces them by its texels' values).
        const float k = f.metallic;
        m.specular = SpecularKind::Glossy;
        m.rhoS = f.baseColor * k + Vec3((1 - k) * f.f0);
        m.rhoD = f.baseColor * ((1 - k) * (1 - f.f0));
        const double alpha = double(f.roughness) * f.roughness;
        const double n = alpha > 0 ? 0.5 / (alpha * alpha) - 0.5 : 1e4;
        m.phongExponent = float(std::min(1e4, std::max(1.0, n)));
        const float sum = maxComponent(m.rhoD + m.rhoS);
        if (sum > 1) {
            m.rhoD = m.rhoD / sum;
            m.rhoS = m.rhoS / sum;
        }
    }
    // The dielectric coat's F0 = ((n − 1)/(n + 1))² of KHR_materials_ior (1.5: 0.04).
    float f0Of(const tinygltf::Material& g, const std::string& field) {
        const double ior = extensionNumber(g, "KHR_materials_ior", "ior", 1.5, field, 1.0, 10.0);
        return float(((ior - 1) / (ior + 1)) * ((ior - 1) / (ior + 1)));
    }

    void noteIgnored(const std::string& what) {
        if (ignoredTextures_.find(what) == std::string::npos)
            ignoredTextures_ += (ignoredTextures_.empty() ? "" : ", ") + what;
    }

    // The encoded bytes of an embedded glTF image (images[i] with a bufferView and mimeType, or a
    // data: URI), its MIME type, and the field that names them in messages.
    std::vector<unsigned char> embeddedImageBytes(const json& image, const std::string& ifield, std::string& mime,
                                                  std::string& efield) {
        if (auto m = image.find("mimeType"); m != image.end()) {
            if (!m->is_string()) fail(ifield + ".mimeType", "a string", showJson(*m));
            mime = m->get<std::string>();
        }
        std::vector<unsigned char> bytes;
        if (auto uri = image.find("uri"); uri != image.end()) {
            efield = ifield + ".uri";
            if (!uri->is_string()) fail(efield, "a string", showJson(*uri));
            std::string decodedMime;
            if (!tinygltf::DecodeDataURI(&bytes, decodedMime, uri->get<std::string>(), 0, false) || bytes.empty())
                fail(efield, "a base64 data: URI of an image/png or image/jpeg",
                     "\"" + uri->get<std::string>().substr(0, 40) + "...\"");
            if (!decodedMime.empty()) mime = decodedMime;
            return bytes;
        }
        efield = ifield + ".bufferView";
        const int view = intIn(image, "bufferView", ifield, 0, int(model_.bufferViews.size()) - 1, -1);
        if (view < 0) fail(ifield, "a uri or a bufferView", "neither");
        if (mime.empty()) fail(ifield + ".mimeType", "image/png or image/jpeg (required with a bufferView)", "none");
        const tinygltf::BufferView& bv = model_.bufferViews[size_t(view)];
        if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size() ||
            bv.byteOffset + bv.byteLength > model_.buffers[size_t(bv.buffer)].data.size())
            fail(at("bufferViews", size_t(view)), "a byte range inside its buffer",
                 std::to_string(bv.byteLength) + " bytes from " + std::to_string(bv.byteOffset));
        const auto& data = model_.buffers[size_t(bv.buffer)].data;
        bytes.assign(data.begin() + std::ptrdiff_t(bv.byteOffset),
                     data.begin() + std::ptrdiff_t(bv.byteOffset + bv.byteLength));
        return bytes;
    }

    // The Scene::textures index of a textureInfo {index, texCoord, extensions}: its image a file
    // beside the scene or embedded (a bufferView, as in a .glb, or a data: URI).
    int textureFor(const json& info, const std::string& field, TextureEncoding encoding) {
        if (!info.is_object()) fail(field, "a textureInfo object", showJson(info));
        const int index = intIn(info, "index", field, -1, int(textures_.textures.size()) - 1, -1);
        if (index < 0)
            fail(field + ".index", "a texture index below " + std::to_string(textures_.textures.size()), "none");
        int texCoord = intIn(info, "texCoord", field, 0, 1, 0);
        TextureTransform transform;
        if (auto ext = info.find("extensions"); ext != info.end() && ext->is_object()) {
            if (auto tt = ext->find("KHR_texture_transform"); tt != ext->end()) {
                const std::string tf = field + ".extensions.KHR_texture_transform";
                if (!tt->is_object()) fail(tf, "an object", showJson(*tt));
                pairIn(*tt, "offset", tf, transform.offset);
                pairIn(*tt, "scale", tf, transform.scale);
                if (auto r = tt->find("rotation"); r != tt->end()) {
                    if (!r->is_number() || !std::isfinite(r->get<double>()))
                        fail(tf + ".rotation", "a number of radians", showJson(*r));
                    transform.rotation = float(r->get<double>());
                }
                texCoord = intIn(*tt, "texCoord", tf, 0, 1, texCoord);
            }
        }
        const json& t = textures_.textures[size_t(index)];
        const std::string tfield = at("textures", size_t(index));
        if (!t.is_object()) fail(tfield, "an object", showJson(t));
        const int source = intIn(t, "source", tfield, 0, int(textures_.images.size()) - 1, -1);
        if (source < 0)
            fail(tfield + ".source", "an image index below " + std::to_string(textures_.images.size()), "none");
        Texture tex;
        const int sampler = intIn(t, "sampler", tfield, 0, int(textures_.samplers.size()) - 1, -1);
        if (sampler >= 0) {
            const json& s = textures_.samplers[size_t(sampler)];
            const std::string sf = at("samplers", size_t(sampler));
            if (!s.is_object()) fail(sf, "an object", showJson(s));
            tex.wrapU = wrapIn(s, "wrapS", sf);
            tex.wrapV = wrapIn(s, "wrapT", sf);
        }
        tex.transform = transform;
        tex.texCoord = texCoord;
        const json& image = textures_.images[size_t(source)];
        const std::string ifield = at("images", size_t(source));
        if (!image.is_object()) fail(ifield, "an object", showJson(image));
        auto uri = image.find("uri");
        const bool inFile = uri != image.end() && uri->is_string() && uri->get<std::string>().rfind("data:", 0) != 0;
        // Shared by every use with the same image, sampler, coordinates and transform.
        const std::string key =
            std::to_string(source) + "/" + std::to_string(sampler) + "/" + std::to_string(texCoord) + "/" +
            show(transform.offset[0]) + "," + show(transform.offset[1]) + "," + show(transform.scale[0]) + "," +
            show(transform.scale[1]) + "," + show(transform.rotation) + "/" + std::to_string(int(encoding));
        if (auto it = textureIndex_.find(key); it != textureIndex_.end()) return it->second;
        if (inFile) {
            tex.path = resolveInsideFolder(file_, ifield + ".uri", percentDecode(uri->get<std::string>()));
            tex.image = loadTextureImage(file_, ifield + ".uri", tex.path, encoding);  // colour: sRGB, data: linear
        } else {
            // Embedded, as Blender's .glb export writes them: a bufferView or a data: URI.
            std::string mime, efield;
            const std::vector<unsigned char> bytes = embeddedImageBytes(image, ifield, mime, efield);
            tex.path = file_ + "#" + ifield;
            tex.image = loadEmbeddedTextureImage(file_, efield, bytes, mime, encoding);
        }
        scene_.textures.push_back(std::move(tex));
        const int added = int(scene_.textures.size()) - 1;
        textureIndex_[key] = added;
        return added;
    }

    // An optional integer `key` of `object` in [lo, hi]; `fallback` when absent.
    int intIn(const json& object, const char* key, const std::string& field, int lo, int hi, int fallback) {
        auto it = object.find(key);
        if (it == object.end()) return fallback;
        if (!it->is_number_integer() || it->get<int64_t>() < lo || it->get<int64_t>() > hi)
            fail(field + "." + key, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                 showJson(*it));
        return int(it->get<int64_t>());
    }
    void pairIn(const json& object, const char* key, const std::string& field, float out[2]) {
        auto it = object.find(key);
        if (it == object.end()) return;
        if (!it->is_array() || it->size() != 2 || !(*it)[0].is_number() || !(*it)[1].is_number() ||
            !std::isfinite((*it)[0].get<double>()) || !std::isfinite((*it)[1].get<double>()))
            fail(field + "." + key, "2 finite numbers", showJson(*it));
        out[0] = float((*it)[0].get<double>());
        out[1] = float((*it)[1].get<double>());
    }
    TextureWrap wrapIn(const json& sampler, const char* key, const std::string& field) {
        const int code = intIn(sampler, key, field, 0, 1 << 30, 10497);
        if (code == 10497) return TextureWrap::Repeat;
        if (code == 33071) return TextureWrap::Clamp;
        if (code == 33648) return TextureWrap::Mirror;
        fail(field + "." + key, "10497 (REPEAT), 33071 (CLAMP_TO_EDGE) or 33648 (MIRRORED_REPEAT)",
             std::to_string(code));
    }

    // ---- KHR_lights_punctual
    void addLight(const tinygltf::Value& ext, const Transform& world, const std::string& nodeField) {
        std::string field = nodeField + ".extensions.KHR_lights_punctual.light";
        if (!ext.IsObject() || !ext.Has("light") || !ext.Get("light").IsInt()) fail(field, "a light index", "none");
        int index = ext.Get("light").Get<int>();
        if (index < 0 || size_t(index) >= model_.lights.size())
            fail(field, "a light index below " + std::to_string(model_.lights.size()), std::to_string(index));
        const tinygltf::Light& g = model_.lights[size_t(index)];
        std::string lf = "extensions.KHR_lights_punctual." + at("lights", size_t(index));
        Vec3 c = g.color.empty() ? Vec3(1.0f) : color(g.color, 3, lf + ".color", 1e30);
        double intensity = factor(g.intensity, lf + ".intensity", 0, 1e30);
        Vec3 radiometric = c * float(intensity / kLumensPerWatt);
        Light l;
        l.name = g.name.empty() ? file_ + ":" + lf : g.name;
        l.position = world.point(Vec3(0.0f));
        Vec3 axis = world.vector(Vec3(0, 0, -1));  // glTF lights and cameras look down -Z
        if (g.type == "point") {
            l.type = LightType::Point;
            l.intensity = radiometric;
        } else if (g.type == "spot") {
            l.type = LightType::Spot;
            l.intensity = radiometric;
            l.direction = normalize(axis);
            double inner = factor(g.spot.innerConeAngle, lf + ".spot.innerConeAngle", 0, kPiD / 2);
            double outer = factor(g.spot.outerConeAngle, lf + ".spot.outerConeAngle", 0, kPiD / 2);
            if (!(outer > 0) || inner > outer)
                fail(lf + ".spot", "0 <= innerConeAngle <= outerConeAngle <= pi/2, outer > 0",
                     show(inner) + ", " + show(outer));
            l.cosInner = float(std::cos(inner));
            l.cosOuter = float(std::cos(outer));
        } else if (g.type == "directional") {
            l.type = LightType::Directional;
            l.direction = normalize(axis);
            l.irradiance = radiometric;
        } else {
            fail(lf + ".type", "point, spot or directional", "\"" + g.type + "\"");
        }
        scene_.lights.push_back(l);
    }

    // ---- Camera: the first perspective camera met in node order.
    void readCamera(int index, const Transform& world) {
        if (size_t(index) >= model_.cameras.size())
            fail("nodes[].camera", "a camera index below " + std::to_string(model_.cameras.size()),
                 std::to_string(index));
        const tinygltf::Camera& g = model_.cameras[size_t(index)];
        std::string field = at("cameras", size_t(index));
        if (g.type != "perspective") fail(field + ".type", "perspective", "\"" + g.type + "\"");
        Camera c;
        c.vfovDegrees =
            float(factor(g.perspective.yfov, field + ".perspective.yfov", 1e-6, kPiD - 1e-6) * 180.0 / kPiD);
        c.height = 256;
        c.width = 256;
        if (g.perspective.aspectRatio > 0) {
            double aspect = factor(g.perspective.aspectRatio, field + ".perspective.aspectRatio", 1e-3, 1e3);
            c.width = std::max(1, std::min(16384, int(std::lround(256 * aspect))));
        }
        c.position = world.point(Vec3(0.0f));
        Vec3 forward = world.vector(Vec3(0, 0, -1));
        Vec3 up = world.vector(Vec3(0, 1, 0));
        if (!(length(forward) > 0) || !(length(cross(forward, up)) > 0))
            fail(field, "a camera node with an invertible transform", "a degenerate one");
        c.lookAt = c.position + normalize(forward);
        c.up = normalize(up);
        result_.hasCamera = true;
        result_.camera = c;
    }

    Scene& scene_;
    const tinygltf::Model& model_;
    const std::string& file_;
    const GltfImportOptions& options_;
    GltfImportResult result_;
    const GltfTextures& textures_;
    std::vector<int> materialIndex_;
    int defaultMaterial_ = -1;
    std::map<std::string, int> textureIndex_;  // Scene::textures of the uses seen so far
    std::string ignoredTextures_;              // texture kinds not read, for one warning
};

}  // namespace

GltfImportResult importGltfFromMemory(Scene& scene, const std::vector<unsigned char>& bytes, const std::string& path,
                                      const GltfImportOptions& options) {
    bool binary = bytes.size() >= 4 && readU32(bytes.data()) == kGlbMagic;
    GlbParts glb;
    if (binary) {
        glb = splitGlb(bytes, path);
    } else {
        glb.json.assign(bytes.begin(), bytes.end());
    }
    json root = parseSceneJson(glb.json, path);
    const GltfTextures textures(root);
    preflight(root, path, binary);
    std::string text = root.dump(-1, ' ', false, json::error_handler_t::replace);

    tinygltf::TinyGLTF loader;
    FsContext fs{folderOf(path)};
    loader.SetFsCallbacks({&fsFileExists, &fsExpandFilePath, &fsReadWholeFile, &fsWriteWholeFile, &fs});
    loader.SetImageLoader(&ignoreImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        if (binary) {
            std::vector<unsigned char> clean = joinGlb(text, glb);
            ok = loader.LoadBinaryFromMemory(&model, &err, &warn, clean.data(), unsigned(clean.size()), fs.folder);
        } else {
            ok = loader.LoadASCIIFromString(&model, &err, &warn, text.data(), unsigned(text.size()), fs.folder);
        }
    } catch (const std::exception& e) {
        err = e.what();
        ok = false;
    }
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    for (auto& c : err)
        if (c == '\n') c = ';';
    if (!ok) failInput(path, "", "a valid glTF 2.0 file", "tinygltf error: " + (err.empty() ? "unknown" : err));
    return GltfReader(scene, model, path, options, textures).read();
}

GltfImportResult importGltf(Scene& scene, const std::string& path, const GltfImportOptions& options) {
    std::string text = readTextFile(path);
    std::vector<unsigned char> bytes(text.begin(), text.end());
    return importGltfFromMemory(scene, bytes, path, options);
}

Scene loadGltfScene(const std::string& path) {
    Scene scene;
    scene.path = path;
    GltfImportResult r = importGltf(scene, path, GltfImportOptions{});
    if (!r.hasCamera) failInput(path, "cameras", "a camera on some node (the first one in node order is used)", "none");
    scene.camera = r.camera;
    return scene;
}

}  // namespace pcl
