#include "render/path_render.h"

#include <algorithm>

#include "core/clock.h"
#include "core/error.h"
#include "reference/light_tracer.h"
#include "reference/path_tracer.h"

namespace pcl {

PathRenderResult renderPathTraced(const Scene& scene, const SceneGeometry& geometry, const PathRenderSettings& s) {
    if (s.samples == 0 && !(s.seconds > 0.0)) throw InputError("render: give a sample count or a time budget");
    const auto start = Clock::now();
    const int width = scene.camera.width, height = scene.camera.height;
    PathRenderResult r;
    PathTracerSettings pt;
    pt.seed = s.seed;
    pt.threads = s.threads;
    PathTracerStats stats;
    if (s.lightTracing) r.lightTracing = pathsThePathTracerMisses(scene);
    // The light tracer does not follow light through media yet: with one it would add wrong light,
    // without it the image lacks that light. Say so rather than pick either silently.
    if (!r.lightTracing.empty() && scene.hasMedia())
        throw InputError("render: " + scene.path + ": " + r.lightTracing +
                         ", and the light tracer that finds it does not trace media yet; "
                         "--no-light-tracing renders without that light");
    LightTracerSettings lt;
    lt.seed = s.seed;
    lt.threads = s.threads;
    auto lightTrace = [&](uint32_t firstPass, uint32_t passes, Film& film) {
        lt.firstPass = firstPass;
        lt.passes = passes;
        LightTracerStats ls;
        LightTracer(scene, geometry, lt).render(film, &ls);
        r.lightPaths += ls.paths;
        r.lightSplats += ls.splats;
        r.discarded += ls.discarded;
    };
    if (!(s.seconds > 0.0) && !s.fixedPoint) {
        // All samples in one call: progress per tile, no stop between samples.
        pt.firstSample = int(s.firstSample);
        pt.samplesPerPixel = int(s.samples);
        if (s.progress) pt.progress = [&](double f) { s.progress(0, f); };
        r.film = PathTracer(scene, geometry, pt).render(&stats);
        if (!r.lightTracing.empty()) {
            Film splats(width, height);
            lightTrace(s.firstSample, s.samples, splats);
            r.film.merge(splats);
        }
        r.samples = s.samples;
        r.paths = stats.samples;
        r.discarded = stats.discardedSamples;
        r.seconds = since(start);
        return r;
    }
    if (s.fixedPoint) r.sums = FixedPointFilm(width, height);
    else r.film = Film(width, height);
    Film splats(width, height);  // the light tracer's sums, added at the end (doubles)
    pt.samplesPerPixel = 1;
    const auto passesStart = Clock::now();
    for (uint32_t done = 0;; ++done) {
        if (s.samples && done >= s.samples) break;
        if (s.seconds > 0 && !anotherPassFits(since(start), s.seconds, done, since(passesStart))) break;
        if (done > 0 && s.stop && s.stop->load()) {
            r.stopped = true;
            break;
        }
        pt.firstSample = int(s.firstSample + done);
        Film one = PathTracer(scene, geometry, pt).render(&stats);
        if (s.fixedPoint) r.sums.addPass(one);
        else r.film.merge(one);
        if (!r.lightTracing.empty()) {
            Film pass(width, height);
            lightTrace(s.firstSample + done, 1, s.fixedPoint ? pass : splats);
            if (s.fixedPoint) r.sums.addPass(pass);
        }
        r.paths += stats.samples;
        r.discarded += stats.discardedSamples;
        r.samples = done + 1;
        if (s.progress) {
            double fraction = s.samples ? double(r.samples) / s.samples : 0.0;
            if (s.seconds > 0) fraction = std::max(fraction, since(start) / s.seconds);
            s.progress(r.samples, std::min(1.0, fraction));
        }
    }
    if (!r.lightTracing.empty() && !s.fixedPoint) r.film.merge(splats);
    r.seconds = since(start);
    return r;
}

}  // namespace pcl
