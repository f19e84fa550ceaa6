#include "delegate/previewSurface.h"

#include <gtest/gtest.h>

using namespace principled;

namespace {
hd::MaterialNetwork network(std::map<hd::Token, hd::Value> inputs) {
    hd::MaterialNetwork n;
    hd::MaterialNode s;
    s.path = hd::Path("/M/S");
    s.identifier = hd::Token("UsdPreviewSurface");
    s.parameters = std::move(inputs);
    n.nodes.push_back(s);
    n.surfaceTerminal = s.path;
    return n;
}
}  // namespace

TEST(PreviewSurface, FallbacksFollowTheSpec) {
    std::vector<std::string> notes;
    auto r = embree::mapPreviewSurface(network({}), &notes);
    EXPECT_FLOAT_EQ(r.params.baseColor.x, 0.18f);
    EXPECT_FLOAT_EQ(r.params.roughness, 0.5f);
    EXPECT_FLOAT_EQ(r.params.metallic, 0.0f);
    EXPECT_NEAR(r.params.specular, 0.5f, 1e-6f);  // ior 1.5 -> F0 0.04 -> specular 0.5
    EXPECT_NEAR(r.params.clearcoatGloss, 0.99f, 1e-6f);
    EXPECT_TRUE(notes.empty());
}

TEST(PreviewSurface, MapsInputsAndClampsOutOfRange) {
    std::vector<std::string> notes;
    auto r = embree::mapPreviewSurface(
        network({{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.2f, 0.4f, 2.0f))},
                 {hd::Token("metallic"), hd::Value(1.0f)},
                 {hd::Token("roughness"), hd::Value(-3.0f)},
                 {hd::Token("ior"), hd::Value(1.0f)},
                 {hd::Token("clearcoatRoughness"), hd::Value(0.3f)},
                 {hd::Token("sheen"), hd::Value(0.7f)},
                 {hd::Token("emissiveColor"), hd::Value(glm::vec3(1, NAN, -1))}}),
        &notes);
    EXPECT_FLOAT_EQ(r.params.baseColor.z, 1.0f);
    EXPECT_FLOAT_EQ(r.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(r.params.roughness, 0.0f);
    EXPECT_FLOAT_EQ(r.params.specular, 0.0f);
    EXPECT_NEAR(r.params.clearcoatGloss, 0.7f, 1e-6f);
    EXPECT_FLOAT_EQ(r.params.sheen, 0.7f);
    EXPECT_EQ(r.emission, glm::vec3(1, 0, 0));
}

TEST(PreviewSurface, SpecularFromIorMatchesTheDisneyRange) {
    EXPECT_NEAR(embree::specularFromIor(1.5f), 0.5f, 1e-6f);
    EXPECT_FLOAT_EQ(embree::specularFromIor(1.0f), 0.0f);
    EXPECT_FLOAT_EQ(embree::specularFromIor(3.0f), 1.0f);  // clamps above ior ~1.8
}

TEST(PreviewSurface, UnknownShaderIsReported) {
    hd::MaterialNetwork n = network({});
    n.nodes[0].identifier = hd::Token("ND_standard_surface");
    std::vector<std::string> notes;
    embree::mapPreviewSurface(n, &notes);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("ND_standard_surface"), std::string::npos);
}
