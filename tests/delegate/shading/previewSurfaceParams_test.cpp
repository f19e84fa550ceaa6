// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/previewSurfaceParams.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace principled::shading;

TEST(PreviewSurfaceParams, FallbacksFollowTheSpec) {
    ShadedMaterial m = mapPreviewSurface(PreviewSurfaceParams{});
    EXPECT_FLOAT_EQ(m.params.baseColor.x, 0.18f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.5f);
    EXPECT_FLOAT_EQ(m.params.metallic, 0.0f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);  // ior 1.5 -> F0 0.04 -> specular 0.5
    // clearcoatRoughness 0.01: GGX alpha 1e-4, held at GTR1's 0.001 (Disney gloss 1).
    EXPECT_FLOAT_EQ(m.params.clearcoatAlpha, 0.001f);
    EXPECT_NEAR(m.params.clearcoatGloss, 1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(m.opacity, 1.0f);
    EXPECT_FLOAT_EQ(m.opacityThreshold, 0.0f);
    EXPECT_FALSE(m.hasNormalMap);
    EXPECT_EQ(m.tangentNormal, glm::vec3(0, 0, 1));
    EXPECT_FALSE(m.specularWorkflow);
}

TEST(PreviewSurfaceParams, MapsAndClampsLikeTheConstantMapping) {
    PreviewSurfaceParams in;
    in.diffuseColor = {0.2f, 0.4f, 2.0f};
    in.metallic = 1.0f;
    in.roughness = -3.0f;
    in.ior = 1.0f;
    in.clearcoatRoughness = 0.3f;
    in.sheen = 0.7f;
    in.emissiveColor = {1.0f, NAN, -1.0f};
    ShadedMaterial m = mapPreviewSurface(in);
    EXPECT_FLOAT_EQ(m.params.baseColor.z, 1.0f);
    EXPECT_FLOAT_EQ(m.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.0f);
    EXPECT_FLOAT_EQ(m.params.specular, 0.0f);
    EXPECT_NEAR(m.params.clearcoatAlpha, 0.09f, 1e-6f);  // 0.3^2
    EXPECT_NEAR(m.params.clearcoatGloss, 0.01f / 0.099f, 1e-6f);
    EXPECT_FLOAT_EQ(m.params.sheen, 0.7f);
    EXPECT_EQ(m.emission, glm::vec3(1, 0, 0));
}

TEST(PreviewSurfaceParams, SpecularWorkflow) {
    PreviewSurfaceParams in;
    in.useSpecularWorkflow = true;
    in.metallic = 1.0f;  // ignored in the specular workflow
    in.specularColor = {0.04f, 0.02f, 0.02f};
    ShadedMaterial m = mapPreviewSurface(in);
    EXPECT_TRUE(m.specularWorkflow);
    EXPECT_EQ(m.specularColor, in.specularColor);
    EXPECT_FLOAT_EQ(m.params.metallic, 0.0f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);  // max channel 0.04 / 0.08
    EXPECT_FLOAT_EQ(m.params.specularTint, 1.0f);
    // bsdf/ takes F0 explicitly (MaterialParams::specularWorkflow/specularColor) when it has them.
    [](const auto& p, const glm::vec3& f0) {
        if constexpr (requires { p.specularWorkflow; }) {
            EXPECT_TRUE(p.specularWorkflow);
            EXPECT_EQ(p.specularColor, f0);
        }
    }(m.params, in.specularColor);
    // A grey F0 has no tint; an explicit Disney input still overrides.
    in.specularColor = glm::vec3(0.08f);
    in.specular = 0.25f;
    m = mapPreviewSurface(in);
    EXPECT_FLOAT_EQ(m.params.specularTint, 0.0f);
    EXPECT_FLOAT_EQ(m.params.specular, 0.25f);
}

TEST(PreviewSurfaceParams, OpacityAndCutout) {
    PreviewSurfaceParams in;
    in.opacity = 0.3f;
    EXPECT_FLOAT_EQ(mapPreviewSurface(in).presence(), 0.3f);
    in.opacityThreshold = 0.5f;
    EXPECT_FLOAT_EQ(mapPreviewSurface(in).presence(), 0.0f);
    in.opacity = 0.5f;
    EXPECT_FLOAT_EQ(mapPreviewSurface(in).presence(), 1.0f);
    in.opacity = 7.0f;
    in.opacityThreshold = NAN;
    ShadedMaterial m = mapPreviewSurface(in);
    EXPECT_FLOAT_EQ(m.opacity, 1.0f);
    EXPECT_FLOAT_EQ(m.opacityThreshold, 0.0f);
}

TEST(PreviewSurfaceParams, NormalIsUnitAndFinite) {
    PreviewSurfaceParams in;
    in.normal = {0.0f, 0.0f, 0.0f};
    EXPECT_EQ(mapPreviewSurface(in).tangentNormal, glm::vec3(0, 0, 1));
    in.normal = {NAN, 0.0f, INFINITY};
    glm::vec3 n = mapPreviewSurface(in).tangentNormal;
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    in.normal = {3.0f, 0.0f, 1.0f};  // components clamp to [-1,1] first
    ShadedMaterial m = mapPreviewSurface(in);
    EXPECT_NEAR(m.tangentNormal.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_TRUE(m.hasNormalMap);
}

TEST(PreviewSurfaceParams, NothingNonFiniteLeaves) {
    PreviewSurfaceParams in;
    in.diffuseColor = glm::vec3(NAN);
    in.metallic = INFINITY;
    in.roughness = NAN;
    in.clearcoat = -INFINITY;
    in.clearcoatRoughness = NAN;
    in.ior = NAN;
    in.opacity = NAN;
    in.sheen = NAN;
    in.specular = INFINITY;
    ShadedMaterial m = mapPreviewSurface(in);
    const auto& p = m.params;
    for (float v : {p.baseColor.x, p.metallic, p.roughness, p.clearcoat, p.clearcoatGloss,
                    p.specular, p.sheen, p.ior, m.opacity}) {
        EXPECT_TRUE(std::isfinite(v));
    }
    EXPECT_FLOAT_EQ(p.ior, 1.5f);
    EXPECT_NEAR(p.specular, 0.5f, 1e-6f);
}

TEST(PreviewSurfaceParams, SpecularFromIor) {
    EXPECT_NEAR(specularFromIor(1.5f), 0.5f, 1e-6f);
    EXPECT_FLOAT_EQ(specularFromIor(1.0f), 0.0f);
    EXPECT_NEAR(specularFromIor(3.0f), 3.125f, 1e-5f);         // F0 0.25: beyond Burley's [0, 1]
    EXPECT_NEAR(0.08f * specularFromIor(2.42f), 0.1724f, 1e-4f);  // diamond
    EXPECT_FLOAT_EQ(specularFromIor(100.0f), principled::bsdf::kMaxSpecular);
    EXPECT_FLOAT_EQ(specularFromIor(-1.0f), 0.5f);
}
