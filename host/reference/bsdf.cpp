#include "reference/bsdf.h"

#include <cmath>

#include "reference/sampling.h"

namespace pcl {

float fresnelDielectric(float cosI, float etaI, float etaT) {
    cosI = std::min(1.0f, std::max(0.0f, cosI));
    float sinT = etaI / etaT * std::sqrt(std::max(0.0f, 1.0f - cosI * cosI));  // Snell
    if (sinT >= 1.0f) return 1.0f;
    float cosT = std::sqrt(std::max(0.0f, 1.0f - sinT * sinT));
    float rParallel = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
    float rPerpendicular = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

bool refract(Vec3 wo, Vec3 n, float eta, Vec3& wt) {
    float cosI = dot(n, wo);
    float sin2T = eta * eta * std::max(0.0f, 1.0f - cosI * cosI);
    if (sin2T >= 1.0f) return false;
    float cosT = std::sqrt(1.0f - sin2T);
    wt = normalize(-wo * eta + n * (eta * cosI - cosT));
    return true;
}

MixedBsdf::MixedBsdf(const Material& material, Vec3 ns, Vec3 ng)
    : MixedBsdf(material, material.rhoD, material.rhoS, material.phongExponent, ns, ng) {}

MixedBsdf::MixedBsdf(const Material& material, Vec3 rhoD, Vec3 rhoS, float exponent, Vec3 ns, Vec3 ng)
    : m_(material), ns_(ns), ng_(ng) {
    m_.rhoD = rhoD;
    m_.rhoS = rhoS;
    m_.phongExponent = exponent;
    float d = luminance(m_.rhoD);
    float s = m_.specular == SpecularKind::None ? 0.0f : luminance(m_.rhoS);
    if (d + s > 0.0f) {
        pDiffuse_ = d / (d + s);
        pSpecular_ = 1.0f - pDiffuse_;
    }
}

Vec3 MixedBsdf::evalCos(Vec3 wo, Vec3 wi) const {
    if (!sameSide(wo, wi)) return Vec3(0.0f);
    Vec3 n = shadingNormalFacing(wo);
    float cosI = dot(n, wi);
    if (cosI <= 0.0f) return Vec3(0.0f);
    Vec3 f = m_.rhoD * kInvPi;  // Lambert
    if (m_.specular == SpecularKind::Glossy && pSpecular_ > 0.0f) {
        // Normalised Phong (Lafortune & Willems 1994): ρs (e + 2)/(2π) cos^e α, α the angle to
        // the mirror direction; reflects exactly ρs at normal incidence, less elsewhere.
        float cosA = dot(wi, reflect(wo, n));
        if (cosA > 0.0f)
            f += m_.rhoS * ((m_.phongExponent + 2.0f) * (0.5f * kInvPi) * std::pow(cosA, m_.phongExponent));
    }
    return f * cosI;
}

float MixedBsdf::pdf(Vec3 wo, Vec3 wi) const {
    if (!sameSide(wo, wi)) return 0.0f;
    Vec3 n = shadingNormalFacing(wo);
    float cosI = dot(n, wi);
    if (cosI <= 0.0f) return 0.0f;
    float p = pDiffuse_ * cosI * kInvPi;
    if (m_.specular == SpecularKind::Glossy && pSpecular_ > 0.0f)
        p += pSpecular_ * phongLobePdf(dot(wi, reflect(wo, n)), m_.phongExponent);
    return p;
}

bool MixedBsdf::sample(Vec3 wo, float uLobe, float u1, float u2, BsdfSample& out) const {
    if (isBlack()) return false;
    Vec3 n = shadingNormalFacing(wo);
    if (uLobe < pDiffuse_ || m_.specular == SpecularKind::Glossy) {
        // Non-delta lobes: sample one, weight by the mixture density of both (one-sample MIS
        // over lobes, Veach 1997 §9.2.4), so f/pdf stays bounded.
        if (uLobe < pDiffuse_) out.wi = sampleCosineHemisphere(n, u1, u2);
        else out.wi = samplePhongLobe(reflect(wo, n), m_.phongExponent, u1, u2);
        out.pdf = pdf(wo, out.wi);
        if (out.pdf <= 0.0f) return false;
        out.weight = evalCos(wo, out.wi) / out.pdf;
        out.delta = false;
        return true;
    }
    // Delta lobes. The lobe choice probability divides ρs: weight = ρs / pSpecular.
    out.delta = true;
    out.weight = m_.rhoS / pSpecular_;
    float u = (uLobe - pDiffuse_) / pSpecular_;  // reused in [0,1) for reflect vs refract
    if (m_.specular == SpecularKind::Mirror) {
        out.wi = reflect(wo, n);
        out.pdf = pSpecular_;
        return sameSide(wo, out.wi);
    }
    // Dielectric: ng points outside; the ray arrives from outside if wo is on that side.
    bool entering = dot(ng_, wo) > 0.0f;
    float etaI = entering ? 1.0f : m_.ior, etaT = entering ? m_.ior : 1.0f;
    float F = fresnelDielectric(dot(n, wo), etaI, etaT);
    // Choose reflection with probability F and refraction with 1 - F: the Fresnel factors
    // cancel in the weight (f/pdf = ρs F / F = ρs (1-F)/(1-F)).
    if (u < F) {
        out.wi = reflect(wo, n);
        out.pdf = pSpecular_ * F;
        return sameSide(wo, out.wi);
    }
    if (!refract(wo, n, etaI / etaT, out.wi)) return false;  // cannot happen: F = 1 under TIR
    out.pdf = pSpecular_ * (1.0f - F);
    // Radiance mode (pbrt-v4's DielectricBxDF): radiance arriving from the etaT side scales by
    // (etaI/etaT)² as it crosses to wo's side.
    out.radianceScale = (etaI / etaT) * (etaI / etaT);
    out.weight *= out.radianceScale;
    return dot(ng_, wo) * dot(ng_, out.wi) < 0.0f;  // it must cross the geometric surface
}

}  // namespace pcl
