// SPDX-License-Identifier: Apache-2.0
// The facade: builds the lobes of a model, picks one per sample with probabilities that depend
// on wo only, and combines them into the one-sample mixture (eval, pdf, sample agree exactly).
#include "bsdf/bsdf.h"

#include <bit>

#include "bsdf/bumpShadowing.h"
#include "bsdf/disney.h"
#include "bsdf/ue4.h"

namespace principled::bsdf {

Bsdf::Bsdf(const MaterialParams& params, const Options& options)
    : _set(options.model == Model::UE4 ? buildUe4(params, options) : buildDisney(params, options)) {
    _set.deltaMask &= _set.mask;
    _lobes = _set.mask;
    _deltaOnly = _lobes != 0 && (_set.deltaMask == _lobes);
    _weightDiffuse = _set.lambertDiffuse ? _set.lambert.selectionWeight(glm::vec3(0.0f, 0.0f, 1.0f))
                                         : _set.diffuse.selectionWeight(glm::vec3(0.0f, 0.0f, 1.0f));
    _weightSheen = _set.sheen.selectionWeight(glm::vec3(0.0f, 0.0f, 1.0f));
    _weightTrans = _set.transmission.weight;
    if (_lobes & lobeBit(Lobe::Clearcoat)) _ccPiLogA2 = _set.clearcoat.dist.piLogA2();
    if (_lobes & lobeBit(Lobe::Specular)) _specK = _set.specular.dist.constants();
}

namespace {

// The switch below is the whole dispatch: no virtual calls in the per-ray path.
template <typename Fn>
auto withLobe(const LobeSet& s, bool inside, Lobe l, Fn&& fn) {
    switch (l) {
        case Lobe::Diffuse:
            return s.lambertDiffuse ? fn(s.lambert) : fn(s.diffuse);
        case Lobe::Sheen:
            return fn(s.sheen);
        case Lobe::Specular:
            return fn(s.specular);
        case Lobe::Clearcoat:
            return fn(s.clearcoat);
        case Lobe::Transmission:
        default:
            return fn(inside ? s.transmissionInside : s.transmission);
    }
}

constexpr LobeMask kDiffuseBit = lobeBit(Lobe::Diffuse), kSheenBit = lobeBit(Lobe::Sheen),
                   kSpecBit = lobeBit(Lobe::Specular), kCoatBit = lobeBit(Lobe::Clearcoat),
                   kTransBit = lobeBit(Lobe::Transmission);

}  // namespace

Bsdf::View Bsdf::prepare(const glm::vec3& woIn) const {
    View v;
    bool transmissive = _set.mask & kTransBit;
    if (_set.thin) {
        v.flip = woIn.z < 0.0f ? -1.0f : 1.0f;
        v.active = _set.mask;
    } else if (transmissive && woIn.z < 0.0f) {
        // Inside a solid: the reflective lobes describe the outside only (pbrt-v3 issue #313).
        v.flip = -1.0f;
        v.inside = true;
        v.active = kTransBit;
    } else {
        v.active = _set.mask;
    }
    const glm::vec3 wo = bendToHemisphere(glm::vec3(woIn.x, woIn.y, woIn.z * v.flip), 1.0f);
    v.wo = wo;
    const LobeMask a = v.active;
    // Schlick 1994, eq. 15: (1 - cos)^5, shared by the diffuse, specular and clearcoat terms
    // (schlickWeight clamps, so max(wo.z, 0) of the selection weights gives the same value).
    const float fv = schlickWeight(wo.z);
    v.fv = fv;
    v.inv4CosO = 1.0f / (4.0f * wo.z);
    // The lobes' selectionWeight(wo), written out so the probabilities stay in registers.
    float w0 = 0.0f, w1 = 0.0f, w2 = 0.0f, w3 = 0.0f, w4 = 0.0f;
    if (a & kDiffuseBit) w0 = std::max(_weightDiffuse, 0.0f);
    if (a & kSheenBit) w1 = std::max(_weightSheen, 0.0f);
    if (a & kSpecBit) {
        const Specular& sp = _set.specular;
        glm::vec3 F = sp.fModel == SpecularFresnel::Schlick
                          ? glm::mix(sp.f0, glm::vec3(1.0f), schlickWeight(std::max(wo.z, 0.0f)))
                          : sp.fresnel(std::max(wo.z, 0.0f));
        w2 = std::max(sp.weight * luminance(F), 0.0f);
        v.g1Spec = sp.dist.G1(wo);
        v.g1SpecK = v.g1Spec * v.inv4CosO;
    }
    if (a & kCoatBit) {
        w3 = std::max(_set.clearcoat.weight * schlickFresnel(0.04f, std::max(wo.z, 0.0f)), 0.0f);
        constexpr Ggx kG{0.25f, 0.25f};  // the fixed clearcoat G alpha (clearcoat.h)
        v.g1Coat = kG.G1(wo);
    }
    if (a & kTransBit) {
        w4 = std::max(_weightTrans, 0.0f);
        v.g1Trans = _set.transmission.dist.G1(wo);
    }
    // Same order of additions as summing over k = 0..4 (inactive lobes add exact zeros).
    float sum = w0 + w1 + w2 + w3 + w4;
    if (sum > 0.0f) {
        // inactive lobes stay 0 (0 / sum = 0)
        v.prob = {w0 / sum, w1 / sum, w2 / sum, w3 / sum, w4 / sum};
    } else {
        float inv = 1.0f / float(std::popcount(a));
        for (int k = 0; k < kLobeCount; ++k) v.prob[k] = (a & (1u << k)) ? inv : 0.0f;
    }
    return v;
}

Bsdf::View Bsdf::prepare(const glm::vec3& woIn, const glm::vec3& smoothNormal) const {
    View v = prepare(woIn);
    // Mirrored like wo and wi when the lobes' frame is flipped (thin or inside).
    const glm::vec3 n0(smoothNormal.x, smoothNormal.y, smoothNormal.z * v.flip);
    if (n0 != glm::vec3(0.0f, 0.0f, 1.0f)) {
        v.smoothNormal = n0;
        v.bumped = true;
    }
    return v;
}

LobeMask Bsdf::sharpLobes(float maxAlpha) const {
    LobeMask sharp = _set.deltaMask;
    auto narrow = [&](const Ggx& g) { return std::max(g.ax, g.ay) <= maxAlpha; };
    if ((_lobes & kSpecBit) && narrow(_set.specular.dist)) sharp |= kSpecBit;
    if ((_lobes & kCoatBit) && _set.clearcoat.dist.alpha <= maxAlpha) sharp |= kCoatBit;
    if ((_lobes & kTransBit) && narrow(_set.transmission.dist) && narrow(_set.transmissionInside.dist))
        sharp |= kTransBit;
    return sharp & _lobes;
}

Bsdf::View Bsdf::restrict(const View& view, LobeMask lobes) const {
    if ((view.active & lobes) == view.active) return view;  // nothing to take out
    View v = view;
    v.active &= lobes;
    float sum = 0.0f;
    for (int k = 0; k < kLobeCount; ++k) {
        if (!(v.active & (1u << k))) v.prob[k] = 0.0f;
        sum += v.prob[k];
    }
    if (sum > 0.0f) {
        for (float& p : v.prob) p /= sum;  // divided, as prepare() does: the same probabilities
    } else {
        const int n = std::popcount(v.active);
        for (int k = 0; k < kLobeCount; ++k) v.prob[k] = (v.active & (1u << k)) ? 1.0f / float(n) : 0.0f;
    }
    return v;
}

std::array<float, kLobeCount> Bsdf::lobeProbabilities(const glm::vec3& wo) const {
    return prepare(wo).prob;
}

glm::vec3 Bsdf::eval(const glm::vec3& woIn, const glm::vec3& wiIn, float* pdfOut,
                     LobeValues* perLobe) const {
    return eval(prepare(woIn), wiIn, pdfOut, perLobe);
}

glm::vec3 Bsdf::eval(const View& v, const glm::vec3& wiIn, float* pdfOut,
                     LobeValues* perLobe) const {
    glm::vec3 wi(wiIn.x, wiIn.y, wiIn.z * v.flip);
    float pdf;
    glm::vec3 f = evalLive(v, wi, v.active & ~_set.deltaMask, &pdf, perLobe);
    if (pdfOut) *pdfOut = pdf;
    return f;
}

// All non-delta lobes in one pass: the half vector, cos^2 theta_d and the wo terms of the View
// are shared; each lobe's value and density use the formulas of its eval() and pdf() with the
// divisions folded into per-material / per-view reciprocals (equal up to float rounding).
glm::vec3 Bsdf::evalLive(const View& v, const glm::vec3& wi, LobeMask live, float* pdfOut,
                         LobeValues* perLobe) const {
    if (perLobe) perLobe->fill(glm::vec3(0.0f));
    const glm::vec3& wo = v.wo;
    glm::vec3 f(0.0f);
    float pdf = 0.0f;
    const bool upper = wo.z > 0.0f && wi.z > 0.0f;
    if (live & (kDiffuseBit | kSheenBit)) {
        const float cos2d = DisneyDiffuse::cos2ThetaD(wo, wi);
        const float pCos = wo.z > 0.0f ? cosineHemispherePdf(wi) : 0.0f;
        // Only a bumped view pays for the shadowing term (unbumped: no extra multiply).
        const bool shadowed = v.bumped && upper;
        const float shadow = shadowed ? bumpShadowing(v.smoothNormal, wi) : 1.0f;
        if (live & kDiffuseBit) {
            glm::vec3 fk(0.0f);
            if (upper) {
                fk = _set.lambertDiffuse ? _set.lambert.eval(wo, wi)
                                         : _set.diffuse.eval(wo, wi, v.fv, cos2d);
                if (shadowed) fk *= shadow;
            }
            f += fk;
            if (perLobe) (*perLobe)[0] = fk;
            pdf += v.prob[0] * pCos;
        }
        if (live & kSheenBit) {
            glm::vec3 fk = upper ? _set.sheen.eval(cos2d, wi) : glm::vec3(0.0f);
            if (shadowed) fk *= shadow;
            f += fk;
            if (perLobe) (*perLobe)[1] = fk;
            pdf += v.prob[1] * pCos;
        }
    }
    if (live & (kSpecBit | kCoatBit)) {
        glm::vec3 h(0.0f);
        bool hOk = false;
        if (upper) {
            h = wo + wi;
            float l = glm::length(h);
            hOk = l > 0.0f;
            // Divided, not multiplied by 1 / l: the clearcoat GTR1 peak (alpha 0.001) turns a
            // one-ulp change of h.z into a 10% change of D.
            h /= l;
        }
        if (live & kSpecBit) {
            glm::vec3 fk(0.0f);
            float pk = 0.0f;
            if (hOk) fk = _set.specular.evalPdf(wo, wi, h, _specK, v.inv4CosO, v.g1SpecK, &pk);
            f += fk;
            if (perLobe) (*perLobe)[2] = fk;
            pdf += v.prob[2] * pk;
        }
        if (live & kCoatBit) {
            glm::vec3 fk(0.0f);
            float pk = 0.0f;
            if (hOk) fk = _set.clearcoat.evalPdf(wo, wi, h, v.g1Coat, _ccPiLogA2, v.inv4CosO, &pk);
            f += fk;
            if (perLobe) (*perLobe)[3] = fk;
            pdf += v.prob[3] * pk;
        }
    }
    if (live & kTransBit) {
        const Dielectric& t = v.inside ? _set.transmissionInside : _set.transmission;
        float pk;
        glm::vec3 fk = t.evalPdf(wo, wi, v.g1Trans, &pk);
        f += fk;
        if (perLobe) (*perLobe)[4] = fk;
        pdf += v.prob[4] * pk;
    }
    *pdfOut = pdf;
    return f;
}

float Bsdf::pdf(const glm::vec3& woIn, const glm::vec3& wiIn) const {
    View v = prepare(woIn);
    glm::vec3 wi(wiIn.x, wiIn.y, wiIn.z * v.flip);
    float pdf;
    evalLive(v, wi, v.active & ~_set.deltaMask, &pdf, nullptr);
    return pdf;
}

std::optional<BsdfSample> Bsdf::sample(const glm::vec3& woIn, float uLobe,
                                       const glm::vec2& u) const {
    return sample(prepare(woIn), uLobe, u);
}

std::optional<BsdfSample> Bsdf::sample(const View& v, float uLobe, const glm::vec2& u) const {
    // Pick the lobe from the cumulative probabilities and reuse the remainder of uLobe.
    int pick = -1;
    float cdf = 0.0f;
    for (int k = 0; k < kLobeCount; ++k) {
        if (v.prob[k] <= 0.0f) continue;
        pick = k;
        if (uLobe < cdf + v.prob[k]) break;
        cdf += v.prob[k];
    }
    if (pick < 0) return std::nullopt;
    // 0.99999994: the largest float below 1, keeping the remapped number in [0, 1).
    float uSub = std::clamp((uLobe - cdf) / v.prob[pick], 0.0f, 0.99999994f);
    const Lobe lobe = Lobe(pick);
    const bool deltaLobe = _set.deltaMask & (1u << pick);
    if (deltaLobe || !(v.wo.z > 0.0f)) {
        // Delta lobes (and the degenerate wo.z <= 0 case) go through the lobe's own sample().
        std::optional<LobeSample> ls = withLobe(
            _set, v.inside, lobe, [&](const auto& l) { return l.sample(v.wo, u, uSub); });
        if (!ls) return std::nullopt;
        BsdfSample s;
        s.lobe = lobe;
        s.wi = glm::vec3(ls->wi.x, ls->wi.y, ls->wi.z * v.flip);
        if (ls->delta) {
            s.delta = true;
            s.f = ls->f;
            s.pdf = v.prob[pick] * ls->pdf;
            if (!(s.pdf > 0.0f)) return std::nullopt;
            return s;
        }
        s.f = eval(v, s.wi, &s.pdf, nullptr);
        if (!(s.pdf > 0.0f)) return std::nullopt;
        return s;
    }
    // Rough lobes: only the direction is drawn here; the mixture value and density at wi come
    // from one evalLive() (the lobe's own f and pdf would be recomputed there anyway).
    glm::vec3 wi;
    switch (lobe) {
        case Lobe::Diffuse:
        case Lobe::Sheen:
            // Diffuse, Lambert and sheen all sample the cosine-weighted hemisphere.
            wi = squareToCosineHemisphere(u);
            if (wi.z <= 0.0f) return std::nullopt;
            break;
        case Lobe::Specular:
            if (!_set.specular.sampleWi(v.wo, u, &wi)) return std::nullopt;
            break;
        case Lobe::Clearcoat:
            if (!_set.clearcoat.sampleWi(v.wo, u, &wi)) return std::nullopt;
            break;
        case Lobe::Transmission:
        default: {
            const Dielectric& t = v.inside ? _set.transmissionInside : _set.transmission;
            if (!t.sampleWi(v.wo, u, uSub, &wi)) return std::nullopt;
            break;
        }
    }
    BsdfSample s;
    s.lobe = lobe;
    s.f = evalLive(v, wi, v.active & ~_set.deltaMask, &s.pdf, nullptr);
    s.wi = glm::vec3(wi.x, wi.y, wi.z * v.flip);
    if (!(s.pdf > 0.0f)) return std::nullopt;
    return s;
}

}  // namespace principled::bsdf
