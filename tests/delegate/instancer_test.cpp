// PointInstancer placement math: scale, then rotation, then translation, then the instancer.
#include "delegate/instancer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "delegate/hd/sceneDelegate.h"

using namespace principled::embree;

TEST(Instancer, ScaleThenRotateThenTranslateThenInstancer) {
    float h = std::sqrt(0.5f);
    glm::vec4 rotZ90(h, 0, 0, h);  // (real, i, j, k): 90 degrees about +Z
    glm::mat4 instancer(1.0f);
    instancer[3] = glm::vec4(0, 0, 5, 1);
    glm::mat4 proto(1.0f);
    proto[3] = glm::vec4(1, 0, 0, 1);  // the prototype's own op comes first
    glm::mat4 m = instanceTransform(instancer, {10, 0, 0}, rotZ90, {2, 1, 1}, proto);
    glm::vec3 p = glm::vec3(m * glm::vec4(0, 0, 0, 1));
    // (0,0,0) -> proto (1,0,0) -> scale (2,0,0) -> rotate (0,2,0) -> translate (10,2,0) -> +z5.
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 2.0f, 1e-5f);
    EXPECT_NEAR(p.z, 5.0f, 1e-5f);
    // A non-unit quaternion is normalised; a zero one means no rotation.
    glm::mat4 z = instanceTransform(glm::mat4(1.0f), {0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1}, glm::mat4(1.0f));
    EXPECT_EQ(z, glm::mat4(1.0f));
    glm::mat4 big = instanceTransform(glm::mat4(1.0f), {0, 0, 0}, 4.0f * rotZ90, {1, 1, 1}, glm::mat4(1.0f));
    EXPECT_NEAR((big * glm::vec4(1, 0, 0, 0)).y, 1.0f, 1e-5f);
}

namespace {

// An instancer of three instances with a per-instance colour and a primvar of the wrong
// length; every prototype draws all three. Its arrays object is replaced on edit(), as the
// USD scene delegate replaces it on every edit.
struct InstancerDelegate : principled::hd::SceneDelegate {
    using Path = principled::hd::Path;
    using Token = principled::hd::Token;
    using Value = principled::hd::Value;
    std::shared_ptr<const principled::hd::InstancerArrays> arrays = make();
    mutable int primvarQueries = 0;
    std::vector<glm::vec3> colours{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    static std::shared_ptr<const principled::hd::InstancerArrays> make() {
        auto a = std::make_shared<principled::hd::InstancerArrays>();
        a->translations = std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
        return a;
    }
    void edit() { arrays = make(); }
    principled::hd::MeshTopology getMeshTopology(const Path&) const override { return {}; }
    principled::hd::SubdivTags getSubdivTags(const Path&) const override { return {}; }
    glm::dmat4 getTransform(const Path&) const override { return glm::dmat4(1.0); }
    bool getVisible(const Path&) const override { return true; }
    bool getDoubleSided(const Path&) const override { return false; }
    Value get(const Path&, const Token& key) const override {
        if (key == Token("primvars:tint")) return colours;
        if (key == Token("primvars:short")) return std::vector<float>{1.0f};
        return Value();
    }
    Value getIndexedPrimvar(const Path& id, const Token& key, std::vector<int>* indices) const override {
        ++primvarQueries;
        indices->clear();
        return get(id, key);
    }
    std::vector<principled::hd::PrimvarDescriptor> getPrimvarDescriptors(
        const Path&, principled::hd::Interpolation interp) const override {
        if (interp != principled::hd::Interpolation::Vertex) return {};
        return {{Token("primvars:tint"), interp, Token(), false}, {Token("primvars:short"), interp, Token(), false}};
    }
    std::shared_ptr<const principled::hd::InstancerArrays> getInstancerArrays(const Path&) const override {
        return arrays;
    }
    std::vector<int> getInstanceIndices(const Path&, const Path&) const override { return {0, 1, 2}; }
    Path getMaterialId(const Path&) const override { return Path(); }
    principled::hd::MaterialNetwork getMaterialResource(const Path&) const override { return {}; }
    Value getLightParamValue(const Path&, const Token&) const override { return Value(); }
    Value getCameraParamValue(const Path&, const Token&) const override { return Value(); }
};

}  // namespace

TEST(Instancer, PerInstancePrimvarsAreReadOnceForAllPrototypes) {
    using principled::hd::Path;
    InstancerDelegate d;
    InstancerPrimvarCache cache;
    const Path instancer("/PI");
    std::vector<std::string> warnings;
    std::vector<std::vector<InstanceRecord>> perPrototype;
    for (const char* proto : {"/PI/A", "/PI/B", "/PI/C"})
        perPrototype.push_back(computeInstances(&d, instancer, Path(proto), glm::mat4(1.0f), &warnings, &cache));
    EXPECT_EQ(cache.reads(), 1);
    EXPECT_EQ(d.primvarQueries, 2);  // tint and short, once
    ASSERT_EQ(perPrototype[0].size(), 3u);
    ASSERT_TRUE(perPrototype[0][0].primvars);
    EXPECT_EQ(perPrototype[0][0].primvars, perPrototype[2][1].primvars);  // one copy
    ASSERT_EQ(perPrototype[0][0].primvars->size(), 1u);  // "short" has 1 value for 3 instances
    EXPECT_EQ((*perPrototype[1][2].primvars)[0].data[8], 1.0f);  // instance 2's blue
    EXPECT_EQ(warnings.size(), 1u) << "the wrong-length primvar is reported once, not per prototype";

    // An edit replaces the arrays: the next sync reads the new values.
    d.colours[2] = {0.5f, 0.5f, 0.5f};
    d.edit();
    auto again = computeInstances(&d, instancer, Path("/PI/A"), glm::mat4(1.0f), &warnings, &cache);
    EXPECT_EQ(cache.reads(), 2);
    EXPECT_EQ((*again[2].primvars)[0].data[8], 0.5f);
    // With nothing holding the channels any more, they are read again rather than kept alive.
    perPrototype.clear();
    again.clear();
    computeInstances(&d, instancer, Path("/PI/A"), glm::mat4(1.0f), &warnings, &cache);
    EXPECT_EQ(cache.reads(), 3);
}
