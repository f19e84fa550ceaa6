// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/standardSurface.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace principled;
using namespace principled::shading;

namespace {

ShadedMaterial shade(const StandardSurfaceParams& s) {
    return mapPreviewSurface(mapStandardSurface(s));
}

}  // namespace

TEST(StandardSurface, DefaultsAreVersion101AndGiveAGreyDielectric) {
    StandardSurfaceParams s =
        StandardSurfaceParams::defaults(hd::Token("ND_standard_surface_surfaceshader"));
    EXPECT_FLOAT_EQ(s.base, 1.0f);
    EXPECT_FLOAT_EQ(s.baseColor.x, 0.8f);
    ShadedMaterial m = shade(s);
    EXPECT_NEAR(m.params.baseColor.x, 0.8f, 1e-6f);  // base 1 * base_color 0.8
    EXPECT_FLOAT_EQ(m.params.metallic, 0.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.2f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);        // IOR 1.5: F0 0.04 = 0.08 * 0.5
    EXPECT_NEAR(m.params.clearcoatAlpha, 0.01f, 1e-6f);  // coat_roughness 0.1: alpha 0.01
    EXPECT_FLOAT_EQ(m.params.sheen, 0.0f);
    EXPECT_FLOAT_EQ(m.params.sheenTint, 0.0f);
    EXPECT_FLOAT_EQ(m.params.specularTint, 0.0f);
    EXPECT_FLOAT_EQ(m.opacity, 1.0f);
    EXPECT_EQ(m.emission, glm::vec3(0.0f));
    EXPECT_FALSE(m.params.thin);
    // Version 1.0.0 swaps base and base_color defaults; their product is the same.
    StandardSurfaceParams old =
        StandardSurfaceParams::defaults(hd::Token("ND_standard_surface_surfaceshader_100"));
    EXPECT_FLOAT_EQ(old.base, 0.8f);
    EXPECT_FLOAT_EQ(old.baseColor.x, 1.0f);
    EXPECT_NEAR(shade(old).params.baseColor.x, 0.8f, 1e-6f);
}

TEST(StandardSurface, RedMetalMapsOntoDisney) {
    StandardSurfaceParams s;
    ASSERT_TRUE(s.set("base_color", glm::vec4(0.8f, 0.1f, 0.1f, 0.0f), 3));
    ASSERT_TRUE(s.set("metalness", glm::vec4(1.0f), 1));
    ASSERT_TRUE(s.set("specular_roughness", glm::vec4(0.3f), 1));
    EXPECT_FALSE(s.set("coat_color", glm::vec4(1.0f), 3));  // not used by the mapping
    ShadedMaterial m = shade(s);
    EXPECT_NEAR(m.params.baseColor.x, 0.8f, 1e-6f);
    EXPECT_NEAR(m.params.baseColor.y, 0.1f, 1e-6f);
    EXPECT_NEAR(m.params.baseColor.z, 0.1f, 1e-6f);
    EXPECT_FLOAT_EQ(m.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.3f);
}

TEST(StandardSurface, SpecularFromIorAndWeight) {
    StandardSurfaceParams s;
    s.specularIor = 1.3f;
    s.specular = 0.5f;
    float f0 = std::pow((1.3f - 1.0f) / (1.3f + 1.0f), 2.0f);  // 0.017
    ShadedMaterial m = shade(s);
    EXPECT_NEAR(m.params.specular, 0.5f * f0 / 0.08f, 1e-5f);
    EXPECT_FLOAT_EQ(m.params.ior, 1.3f);
    // A grey specular_color scales the strength by its luminance.
    s.specularColor = glm::vec3(0.5f);
    EXPECT_NEAR(shade(s).params.specular, 0.25f * f0 / 0.08f, 1e-5f);
    // High IORs keep their F0 (ior 4: 0.36) up to bsdf::kMaxSpecular (F0 0.5).
    s.specularIor = 4.0f;
    s.specular = 1.0f;
    s.specularColor = glm::vec3(1.0f);
    EXPECT_NEAR(0.08f * shade(s).params.specular, 0.36f, 1e-5f);
    s.specularIor = 50.0f;
    EXPECT_FLOAT_EQ(shade(s).params.specular, principled::bsdf::kMaxSpecular);
}

TEST(StandardSurface, RoughCoatsKeepTheirRoughness) {
    StandardSurfaceParams s;
    s.coat = 1.0f;
    s.coatRoughness = 0.6f;  // alpha 0.36, beyond Disney's gloss range (0.1), given directly
    EXPECT_NEAR(shade(s).params.clearcoatAlpha, 0.36f, 1e-6f);
    EXPECT_NEAR(shade(s).params.clearcoatGloss, 0.0f, 1e-6f);
}

TEST(StandardSurface, LayersEmissionOpacityAndThinWalls) {
    StandardSurfaceParams s;
    s.coat = 0.7f;
    s.coatRoughness = 0.25f;
    s.sheen = 0.5f;
    s.transmission = 0.9f;
    s.subsurface = 0.4f;
    s.emission = 2.0f;
    s.emissionColor = glm::vec3(1.0f, 0.5f, 0.0f);
    s.opacity = glm::vec3(0.3f, 0.6f, 0.9f);
    ASSERT_TRUE(s.set("thin_walled", glm::vec4(1.0f), 1));
    ShadedMaterial m = shade(s);
    EXPECT_FLOAT_EQ(m.params.clearcoat, 0.7f);
    // GGX alpha 0.25^2 = 0.0625, the coat's alpha.
    EXPECT_NEAR(m.params.clearcoatAlpha, 0.0625f, 1e-6f);
    EXPECT_FLOAT_EQ(m.params.sheen, 0.5f);
    EXPECT_FLOAT_EQ(m.params.specTrans, 0.9f);
    EXPECT_FLOAT_EQ(m.params.subsurface, 0.4f);
    EXPECT_NEAR(m.emission.x, 2.0f, 1e-6f);
    EXPECT_NEAR(m.emission.y, 1.0f, 1e-6f);
    EXPECT_NEAR(m.emission.z, 0.0f, 1e-6f);
    EXPECT_NEAR(m.opacity, 0.6f, 1e-6f);  // mean of the opacity colour
    EXPECT_EQ(m.opacityMode, OpacityMode::Presence);
    EXPECT_TRUE(m.params.thin);
}

TEST(StandardSurface, NonFiniteValuesKeepTheDefault) {
    StandardSurfaceParams s;
    EXPECT_TRUE(s.set("specular_roughness", glm::vec4(NAN), 1));
    EXPECT_FLOAT_EQ(s.specularRoughness, 0.2f);
    s.baseColor = glm::vec3(NAN, 2.0f, -1.0f);
    ShadedMaterial m = shade(s);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(m.params.baseColor[i]));
    EXPECT_FLOAT_EQ(m.params.baseColor.y, 1.0f);
}
