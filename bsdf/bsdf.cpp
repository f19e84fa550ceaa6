// SPDX-License-Identifier: Apache-2.0
// The facade: builds the lobes of a model, picks one per sample with probabilities that depend
// on wo only, and combines them into the one-sample mixture (eval, pdf, sample agree exactly).
#include "bsdf/bsdf.h"

#include <bit>

#include "bsdf/disney.h"
#include "bsdf/ue4.h"

namespace principled::bsdf {

Bsdf::Bsdf(const MaterialParams& params, const Options& options)
    : _set(options.model == Model::UE4 ? buildUe4(params, options) : buildDisney(params, options)) {
    _set.deltaMask &= _set.mask;
    _lobes = _set.mask;
    _deltaOnly = _lobes != 0 && (_set.deltaMask == _lobes);
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

}  // namespace

Bsdf::View Bsdf::prepare(const glm::vec3& woIn) const {
    View v;
    bool transmissive = _set.mask & lobeBit(Lobe::Transmission);
    if (_set.thin) {
        v.flip = woIn.z < 0.0f ? -1.0f : 1.0f;
        v.active = _set.mask;
    } else if (transmissive && woIn.z < 0.0f) {
        // Inside a solid: the reflective lobes describe the outside only (pbrt-v3 issue #313).
        v.flip = -1.0f;
        v.inside = true;
        v.active = lobeBit(Lobe::Transmission);
    } else {
        v.active = _set.mask;
    }
    v.wo = bendToHemisphere(glm::vec3(woIn.x, woIn.y, woIn.z * v.flip), 1.0f);
    float sum = 0.0f;
    for (int k = 0; k < kLobeCount; ++k) {
        if (!(v.active & (1u << k))) continue;
        float w = withLobe(_set, v.inside, Lobe(k),
                           [&](const auto& lobe) { return lobe.selectionWeight(v.wo); });
        v.prob[k] = std::max(w, 0.0f);
        sum += v.prob[k];
    }
    if (sum > 0.0f) {
        for (int k = 0; k < kLobeCount; ++k)
            if (v.prob[k] > 0.0f) v.prob[k] /= sum;  // inactive lobes stay 0 (no division)
    } else {
        int n = std::popcount(v.active);
        for (int k = 0; k < kLobeCount; ++k) v.prob[k] = (v.active & (1u << k)) ? 1.0f / n : 0.0f;
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
    if (perLobe) perLobe->fill(glm::vec3(0.0f));
    glm::vec3 wi(wiIn.x, wiIn.y, wiIn.z * v.flip);
    glm::vec3 f(0.0f);
    float pdf = 0.0f;
    LobeMask live = v.active & ~_set.deltaMask;
    for (int k = 0; k < kLobeCount; ++k) {
        if (!(live & (1u << k))) continue;
        withLobe(_set, v.inside, Lobe(k), [&](const auto& lobe) {
            glm::vec3 fk = lobe.eval(v.wo, wi);
            f += fk;
            if (perLobe) (*perLobe)[k] = fk;
            if (pdfOut) pdf += v.prob[k] * lobe.pdf(v.wo, wi);
            return 0;
        });
    }
    if (pdfOut) *pdfOut = pdf;
    return f;
}

float Bsdf::pdf(const glm::vec3& woIn, const glm::vec3& wiIn) const {
    View v = prepare(woIn);
    glm::vec3 wi(wiIn.x, wiIn.y, wiIn.z * v.flip);
    float pdf = 0.0f;
    LobeMask live = v.active & ~_set.deltaMask;
    for (int k = 0; k < kLobeCount; ++k) {
        if (!(live & (1u << k))) continue;
        pdf += v.prob[k] * withLobe(_set, v.inside, Lobe(k),
                                    [&](const auto& lobe) { return lobe.pdf(v.wo, wi); });
    }
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
    std::optional<LobeSample> ls = withLobe(
        _set, v.inside, Lobe(pick), [&](const auto& lobe) { return lobe.sample(v.wo, u, uSub); });
    if (!ls) return std::nullopt;
    BsdfSample s;
    s.lobe = Lobe(pick);
    s.wi = glm::vec3(ls->wi.x, ls->wi.y, ls->wi.z * v.flip);
    if (ls->delta) {
        s.delta = true;
        s.f = ls->f;
        s.pdf = v.prob[pick] * ls->pdf;
        if (!(s.pdf > 0.0f)) return std::nullopt;
        return s;
    }
    // The mixture value and density at wi (identical to eval() and pdf() there).
    s.f = eval(v, s.wi, &s.pdf, nullptr);
    if (!(s.pdf > 0.0f)) return std::nullopt;
    return s;
}

}  // namespace principled::bsdf
