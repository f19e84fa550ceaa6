#include "delegate/hd/renderIndex.h"

#include <gtest/gtest.h>

#include <mutex>

#include "delegate/hd/tokens.h"

namespace hd = principled::hd;

namespace {

// Records the order in which prims sync and which bits they saw.
struct Log {
    std::mutex m;
    std::vector<std::string> order;
    std::map<std::string, hd::DirtyBits> bits;
    int commits = 0;
    void add(const std::string& kind, const hd::Path& id, hd::DirtyBits b) {
        std::lock_guard<std::mutex> l(m);
        order.push_back(kind);
        bits[id.str()] = b;
    }
};

struct R : hd::Rprim {
    Log* log;
    R(const hd::Path& id, Log* l) : Rprim(id), log(l) {}
    void sync(hd::SceneDelegate*, hd::RenderParam*, hd::DirtyBits* b) override {
        log->add("r", id(), *b);
        *b = 0;
    }
};
struct S : hd::Sprim {
    Log* log;
    S(const hd::Path& id, Log* l) : Sprim(id), log(l) {}
    void sync(hd::SceneDelegate*, hd::RenderParam*, hd::DirtyBits* b) override {
        log->add("s", id(), *b);
        *b = 0;
    }
};
struct B : hd::Bprim {
    Log* log;
    B(const hd::Path& id, Log* l) : Bprim(id), log(l) {}
    void sync(hd::SceneDelegate*, hd::RenderParam*, hd::DirtyBits* b) override {
        log->add("b", id(), *b);
        *b = 0;
    }
};

struct FakeDelegate : hd::RenderDelegate {
    Log log;
    hd::RenderParam param;
    const std::vector<hd::Token>& supportedRprimTypes() const override {
        static std::vector<hd::Token> t{hd::tokens::mesh()};
        return t;
    }
    const std::vector<hd::Token>& supportedSprimTypes() const override {
        static std::vector<hd::Token> t{hd::tokens::camera()};
        return t;
    }
    const std::vector<hd::Token>& supportedBprimTypes() const override {
        static std::vector<hd::Token> t{hd::tokens::renderBuffer()};
        return t;
    }
    std::unique_ptr<hd::Rprim> createRprim(const hd::Token&, const hd::Path& id) override {
        return std::make_unique<R>(id, &log);
    }
    std::unique_ptr<hd::Sprim> createSprim(const hd::Token&, const hd::Path& id) override {
        return std::make_unique<S>(id, &log);
    }
    std::unique_ptr<hd::Bprim> createBprim(const hd::Token&, const hd::Path& id) override {
        return std::make_unique<B>(id, &log);
    }
    std::unique_ptr<hd::RenderPass> createRenderPass(hd::RenderIndex*) override { return nullptr; }
    hd::RenderParam* renderParam() override { return &param; }
    void commitResources(hd::ChangeTracker*) override {
        log.order.push_back("commit");
        ++log.commits;
    }
    hd::AovDescriptor defaultAovDescriptor(const hd::Token&) const override { return {}; }
    std::vector<hd::RenderSettingDescriptor> renderSettingDescriptors() const override { return {}; }
    void setRenderSetting(const hd::Token&, const hd::Value&) override {}
    hd::Value renderSetting(const hd::Token&) const override { return {}; }
    unsigned renderSettingsVersion() const override { return 0; }
    std::map<std::string, double> renderStats() const override { return {}; }
};

}  // namespace

TEST(RenderIndex, SyncsBprimsThenSprimsThenRprimsThenCommits) {
    FakeDelegate d;
    hd::RenderIndex index(&d);
    for (int i = 0; i < 20; ++i)
        ASSERT_TRUE(index.insertRprim(hd::tokens::mesh(), nullptr, hd::Path("/m" + std::to_string(i))));
    ASSERT_TRUE(index.insertSprim(hd::tokens::camera(), nullptr, hd::Path("/cam")));
    ASSERT_TRUE(index.insertBprim(hd::tokens::renderBuffer(), nullptr, hd::Path("/buf")));
    index.sync();
    ASSERT_EQ(d.log.order.size(), 23u);
    EXPECT_EQ(d.log.order[0], "b");
    EXPECT_EQ(d.log.order[1], "s");
    for (int i = 2; i < 22; ++i) EXPECT_EQ(d.log.order[i], "r");
    EXPECT_EQ(d.log.order[22], "commit");
    EXPECT_EQ(d.log.bits["/m3"], hd::RprimDirty::AllDirty);
}

TEST(RenderIndex, OnlyDirtyPrimsSyncAgainWithTheirBits) {
    FakeDelegate d;
    hd::RenderIndex index(&d);
    index.insertRprim(hd::tokens::mesh(), nullptr, hd::Path("/a"));
    index.insertRprim(hd::tokens::mesh(), nullptr, hd::Path("/b"));
    index.sync();
    d.log.order.clear();
    unsigned v = index.changeTracker().sceneVersion();
    index.changeTracker().markRprimDirty(hd::Path("/b"), hd::RprimDirty::Transform);
    EXPECT_GT(index.changeTracker().sceneVersion(), v);
    index.sync();
    ASSERT_EQ(d.log.order.size(), 2u);  // one rprim + commit
    EXPECT_EQ(d.log.bits["/b"], hd::RprimDirty::Transform);
    d.log.order.clear();
    index.sync();
    EXPECT_EQ(d.log.order.size(), 1u);  // nothing dirty: only the commit
}

TEST(RenderIndex, RejectsUnsupportedTypesAndDuplicates) {
    FakeDelegate d;
    hd::RenderIndex index(&d);
    EXPECT_FALSE(index.insertRprim(hd::Token("volume"), nullptr, hd::Path("/v")));
    EXPECT_TRUE(index.insertRprim(hd::tokens::mesh(), nullptr, hd::Path("/m")));
    EXPECT_FALSE(index.insertRprim(hd::tokens::mesh(), nullptr, hd::Path("/m")));
    EXPECT_EQ(index.rprimCount(), 1u);
    EXPECT_EQ(index.rprim(hd::Path("/m"))->primId(), 0);
    EXPECT_EQ(index.rprimByPrimId(0), index.rprim(hd::Path("/m")));
    index.removeRprim(hd::Path("/m"));
    EXPECT_EQ(index.rprim(hd::Path("/m")), nullptr);
    EXPECT_EQ(index.rprimByPrimId(0), nullptr);
}
