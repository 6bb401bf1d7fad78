// `render --method auto`: fg or the path tracer, whichever a short pilot says reaches a lower
// error in the same time on this scene at this size. Each candidate renders the image at a
// quarter of its width and height twice with independent seeds (fg one pass each, with the
// settings the full render would use; the path tracer 16 samples per pixel each). With a caustic
// map fg has two candidates: its default eye split (4×4 eye samples of 4 gather rays, each paying
// a caustic estimate) and the caustic-free scenes' 6×6 of 2 (cornell-glossy, whose caustic map
// holds only the glossy floor's light, measured 0.0166 against 0.0222 in RMSE at 30 s with it). The variance of one render
// is half the relMSE between the two; times its cost at full size (the photon pass and the maps
// cost the same at any size, the eye work and the path tracer scale with the pixels) it is the
// error × seconds product that equal-time comparisons measure. The lower product wins. What the
// pilot cannot see: fg's bias (its estimates are blurred, not noisy: cornell-box's fg is 0.2 %
// dark), and noise that only finer pixels resolve. Since 2026-12-03 it measures fg's bias against
// the path tracer's pilot (squaredBias, the pixels fg's caustic light dominates aside, where the
// path tracer's few samples are unsteady) and compares the relMSE each candidate is predicted to
// reach in the budget: errorSeconds / T + biasSquared. On sky-spheres fg's pilot read 1.2-1.5x the
// path tracer's error x time, yet at 30 s its relMSE was 30x (a band where the clay ball meets the
// ground, 1.33x too bright: bias). What its few path-traced samples rarely see,
// the fireflies of caustics from small bright emitters (a sun through a glass ball), is added to
// the path tracer's variance from fg's pilot instead (causticFireflyVariance).
#pragma once
#include <string>
#include <vector>

#include "device/device.h"
#include "image/image.h"
#include "prep/prepared_scene.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace pcl {

struct AutoCandidate {
    std::string name;         // "fg", "fg 6x6x2", "path"
    RenderRequest request;    // what renders it (method and, for the fg split, strata/gather/light)
    double errorSeconds = 0;  // relMSE × seconds at full size (the variance's part)
    double unitSeconds = 0;   // a pass (fg) or a sample per pixel (path) of the full image, predicted
    double fireflyShare = 0;  // path: the share of its variance made of caustic fireflies (causticFireflyVariance)
    double biasSquared = 0;   // fg: the relMSE that does not fall with time (squaredBias against the path tracer)
    std::string tuned;        // fg: how the pilot changed its gather rays and why (empty: unchanged)
};

// fg's gather rays for the indirect part's share of the variance and of the time: a pass at g0
// rays has relative variance V, of which the indirect part's is Vi, and takes T seconds, of which
// the indirect stage's are Ti. With g rays the indirect variance scales by g0/g and its time by
// g/g0, so the error × time (V − Vi + Vi g0/g)(T − Ti + Ti g/g0) is least at
//   g/g0 = sqrt(Vi (T − Ti) / ((V − Vi) Ti)).
// Returns that g rounded, within [1, maxRays] (g0 where a figure is missing or non-positive).
uint32_t gatherRaysForTheIndirectShare(uint32_t g0, double V, double Vi, double T, double Ti, uint32_t maxRays = 16);
// The error × time that formula predicts at g rays.
double predictedErrorSeconds(uint32_t g0, uint32_t g, double V, double Vi, double T, double Ti);
// The relative squared bias between two methods from their independent renders (K ≥ 2 each, the
// same size): per pixel and channel (ā − b̄)² less each mean's variance (s²/K), over ((ā + b̄)/2)²
// + ε, averaged over the pixels `keep` marks (all when empty); less twice its standard error, so
// that noise alone reads 0. An unbiased estimate of the squared difference of their means: against
// the path tracer, fg's bias, which no number of passes removes.
double squaredBias(const std::vector<Image>& a, const std::vector<Image>& b, const std::vector<bool>& keep);
// The relative variance of one part of the image (an AOV) from K ≥ 2 independent renders, each
// pixel's over the squared mean of the whole image (`totals`, the same renders) + ε: the part's
// share of renderVariance when the parts are independent.
double partVariance(const std::vector<Image>& parts, const std::vector<Image>& totals);

struct AutoMethodChoice {
    std::vector<AutoCandidate> candidates;  // fg's first, the path tracer last
    size_t chosen = 0;                      // the lowest predicted relMSE at the budget
    double budgetSeconds = 0;               // the time the choice was made for
    double pilotSeconds = 0;                // wall time of the whole pilot
    double fgDefaultPassSeconds = 0;        // fg's pass at its default settings, as measured
    const AutoCandidate& best() const { return candidates[chosen]; }
    // The relMSE a candidate is predicted to reach in budgetSeconds: errorSeconds / T + biasSquared.
    double predictedRelMse(const AutoCandidate& c) const;
    std::string log() const;  // one line: the choice and every candidate's figures
    // Without a time budget: the time fg's default passes at width × height would take, as the
    // pilot predicts it (fgBudgetSeconds), spent by the winner: its passes, or its samples per
    // pixel if it is the path tracer (1 .. 2^20). An unconfigured render so costs what it did
    // before auto was the default.
    double fgBudgetSeconds(int width, int height) const;
    uint32_t unitsWithoutBudget(int width, int height) const;
};

// The radiance a path-traced caustic sample is worth when it finds its emitter through the
// specular chain, averaged as the caustic light weights it: over the caustic photons' shares
// (their power times the projection map's fraction, as the caustic pass allocates them), each
// emitter's ∫ L² / ∫ L (over the sky's texels by solid angle; an area light's power / (π A));
// delta lights count 0, as the path tracer's light tracer finds their caustics. Per channel;
// zero when no caustic photons leave a non-delta emitter.
Vec3 causticEmitterRadiance(const Scene& scene, const SceneBuffers& buffers);

// The relative variance (relMSE's measure, per pixel and channel, averaged) that one path-traced
// sample per pixel adds through caustic fireflies: at a diffuse point of albedo ρ a BSDF sample
// that passes the specular chain into an emitter of radiance L_e is worth ρ T L_e (T ≤ 1 the
// chain's throughput) with a small probability p, and its mean is the caustic radiance
// L_c = ρ T L_e p; so its variance is about L_c ρ L_e. `caustic`, `albedo` and `mean` are fg's
// pilot images (its caustic and albedo AOVs and the image); same size.
double causticFireflyVariance(const Image& caustic, const Image& albedo, const Image& mean, Vec3 emitterRadiance);

// The pilot on `device` (fg) and the CPU (path tracer) for `request` at the scene camera's size.
AutoMethodChoice chooseRenderMethod(Device& device, const Scene& scene, const PreparedScene& prepared,
                                    const RenderRequest& request);

}  // namespace pcl
