// SPDX-License-Identifier: Apache-2.0
// Value types shared by the BSDF facade and the lobe library: model, lobes, parameters, options.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace principled::bsdf {

/// Which shading model turns the parameters into lobes.
enum class Model : uint8_t { Disney, UE4 };

/// The lobes a material can have. Per-lobe values are reported in this order so the integrator
/// can split light paths into per-lobe AOVs (diffuse, specular, sheen, clearcoat, transmission).
enum class Lobe : uint8_t { Diffuse = 0, Sheen, Specular, Clearcoat, Transmission, Count };
inline constexpr int kLobeCount = static_cast<int>(Lobe::Count);
using LobeMask = uint32_t;
inline constexpr LobeMask lobeBit(Lobe l) { return 1u << static_cast<unsigned>(l); }

/// Material parameters in Disney naming (Burley 2012, "Physically-Based Shading at Disney",
/// section 5.1), plus the 2015 transmission extension. Colours are linear.
/// The largest `specular` the models take: F0 = 0.08 * specular up to 0.5 (an index of
/// refraction of 5.8). Burley's [0, 1] covers indices up to 1.8; UsdPreviewSurface's ior goes
/// beyond (diamond 2.42: F0 0.17, specular 2.15).
inline constexpr float kMaxSpecular = 6.25f;

struct MaterialParams {
    glm::vec3 baseColor{0.82f, 0.67f, 0.16f};
    float subsurface = 0.0f;
    float metallic = 0.0f;
    float specular = 0.5f;
    float specularTint = 0.0f;
    float roughness = 0.5f;
    float anisotropic = 0.0f;
    float sheen = 0.0f;
    float sheenTint = 0.5f;
    float clearcoat = 0.0f;
    float clearcoatGloss = 1.0f;
    /// The clearcoat's GTR1 alpha itself, when >= 0 (UsdPreviewSurface clearcoatRoughness r:
    /// r^2, as GGX roughness reads, up to 1); < 0: from clearcoatGloss (Disney's 0.1 to 0.001).
    float clearcoatAlpha = -1.0f;
    float specTrans = 0.0f;  ///< Burley 2015 specular transmission weight.
    float ior = 1.5f;        ///< Used by transmission.
    bool thin = false;       ///< Thin-surface transmission (no refraction of the path).
    /// UsdPreviewSurface specular workflow (useSpecularWorkflow = 1): specularColor is F0 and
    /// metallic, specular and specularTint are ignored.
    bool specularWorkflow = false;
    glm::vec3 specularColor{0.0f};
    /// Multiplies the diffuse-like lobes (diffuse, subsurface, sheen), not the specular ones:
    /// UsdPreviewSurface opacityMode "transparent" scales what is not specular by the opacity
    /// (clear glass keeps its reflections). [0, 1].
    float diffuseScale = 1.0f;
};

/// Settings that trade speed against accuracy; every one is charted in bench/.
struct Options {
    Model model = Model::Disney;
    bool legacySpecularG = false;  ///< Burley 2012 course-notes G remap (0.5 + 0.5 r)^2.
    /// Disney specular Fresnel shaped like Cycles 3.4's Principled v1 (SpecularFresnel::
    /// DielectricBlend, eta from `specular`) instead of Schlick's (docs/hosts.md measures it).
    bool dielectricFresnel = false;
    bool vndfSampling = true;      ///< Heitz 2018 visible normals; false = classic D sampling.
    float deltaRoughness = 1e-3f;  ///< Below this roughness specular becomes a perfect mirror.
    bool pruneLobes = true;        ///< Skip lobes whose weight is below pruneCutoff.
    float pruneCutoff = 1e-4f;
    /// Lobes allowed at all (diagnostics: e.g. only Diffuse to measure Burley diffuse alone).
    LobeMask lobeMask = (1u << kLobeCount) - 1u;
};

/// Per-lobe contributions of one evaluation, f * |cos(theta_i)| each; they sum to eval().
using LobeValues = std::array<glm::vec3, kLobeCount>;

struct BsdfSample {
    glm::vec3 wi{0.0f};
    glm::vec3 f{0.0f};    ///< f(wo, wi) * |cos(theta_i)| (for a delta lobe: the weight times pdf).
    float pdf = 0.0f;     ///< Solid-angle pdf of the whole mixture (for a delta lobe: the lobe's pick probability).
    Lobe lobe = Lobe::Diffuse;
    bool delta = false;   ///< True when wi came from a perfect-mirror or smooth-glass lobe.
};

}  // namespace principled::bsdf
