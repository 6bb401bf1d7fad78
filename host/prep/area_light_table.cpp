#include "prep/area_light_table.h"

namespace pcl {

AreaLightTable buildAreaLightTable(const SceneBuffers& buffers, size_t primitiveCount) {
    AreaLightTable t;
    t.lightOfPrim.assign(primitiveCount, PCL_NO_HIT);
    const size_t n = buffers.lights.size();
    std::vector<double> s(n, 0.0);
    double total = 0.0;
    float totalF = 0.0f;
    size_t last = n;
    for (size_t l = 0; l < n; ++l) {
        const PclLight& L = buffers.lights[l];
        if (L.type != PCL_LIGHT_TRIANGLE) continue;
        if (L.prim < primitiveCount) t.lightOfPrim[L.prim] = uint32_t(l);
        // The kernel's s_L: (Φr + Φg + Φb)/3 in float; the total summed in float in light order.
        const float sf = (L.power[0] + L.power[1] + L.power[2]) / 3.0f;
        if (!(sf > 0.0f)) continue;
        s[l] = sf;
        total += sf;
        totalF += sf;
        last = l;
        ++t.areaLights;
    }
    t.cdf.assign(n, 0.0f);
    double running = 0.0;
    for (size_t l = 0; l < n; ++l) {
        running += s[l];
        t.cdf[l] = total > 0.0 ? float(running / total) : 0.0f;
        if (l >= last && last < n) t.cdf[l] = 1.0f;
    }
    t.total = t.areaLights ? totalF : 0.0f;
    return t;
}

}  // namespace pcl
