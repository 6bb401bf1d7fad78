// Photon maps as PLY (`photoncl photons`): one vertex per stored photon with its
// position, decoded power (W), decoded direction and surface normal (unit), map (0 global, 1 caustic) and bounce,
// for viewing in a point-cloud tool and diffing between devices. Binary little-endian by
// default, ASCII on request; the file is written to a temporary name in the destination folder
// and renamed, so the final name never holds a partial file.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/photon_pass.h"
#include "shared/types.h"

namespace pcl {

// One photon as the PLY holds it: the PclPhoton record decoded (kernels/README.md, "Photon
// record"; the decoders are kernels/shared/sampling.h's photon_rgbe_decode / photon_dir_decode).
struct PlyPhoton {
    float x = 0, y = 0, z = 0;     // position
    float r = 0, g = 0, b = 0;     // power, W
    float dx = 0, dy = 0, dz = 0;  // the record's direction (centre of its θ/φ byte cell), unit
    float nx = 0, ny = 0, nz = 1;  // the surface normal on the side the photon arrived from, unit
    uint8_t map = 0;               // 0 global, 1 caustic
    uint8_t bounce = 0;            // bounces before this hit
};

constexpr uint8_t kPlyMapGlobal = 0, kPlyMapCaustic = 1;

PlyPhoton decodePhoton(const PclPhoton& p, uint8_t map);

// What the comment line records.
struct PhotonPlyMetadata {
    std::string scene, device;
    uint64_t seed = 0;
    uint32_t globalPhotons = 0, causticPhotons = 0;  // paths emitted per pass (0: pass not run)
};

// Writes maps.global (map 0) then maps.caustic (map 1), in map order. Throws InputError when the
// file cannot be written (nothing is left under `path` then).
void writePhotonPly(const std::string& path, const PhotonMaps& maps, const PhotonPlyMetadata& metadata,
                    bool ascii = false);

// Reads a PLY written by writePhotonPly (either format; other layouts are rejected with an
// InputError). For tests and tools.
struct PhotonPly {
    bool ascii = false;
    size_t declaredVertices = 0;
    std::vector<std::string> comments;  // without the "comment " prefix
    std::vector<PlyPhoton> photons;
};
PhotonPly readPhotonPly(const std::string& path);

}  // namespace pcl
