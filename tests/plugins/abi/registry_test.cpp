// SPDX-License-Identifier: Apache-2.0
// PluginRegistry: discovery from hand-written plugInfo.json files in a temp dir, sorting,
// lookup, and the exact messages for malformed manifests and failed loads.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "plugins/registry/pluginRegistry.h"

using namespace principled::plugins;
namespace fs = std::filesystem;

namespace {

class RegistryTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        _root = fs::temp_directory_path() /
                ("principled_registry_" + std::to_string(getpid()) + "_" + info->name());
        fs::remove_all(_root);
        fs::create_directories(_root);
    }
    void TearDown() override { fs::remove_all(_root); }

    /// Writes dir/plugInfo.json (dir relative to the temp root) and returns its path.
    std::string write(const std::string& dir, const std::string& text) {
        fs::create_directories(_root / dir);
        fs::path p = _root / dir / "plugInfo.json";
        std::ofstream(p) << text;
        return p.string();
    }
    static std::string manifest(const std::string& name, const std::string& lib,
                                const std::string& type, const std::string& display, int priority) {
        return R"({"Plugins":[{"Name":")" + name + R"(","Type":"library","LibraryPath":")" + lib +
               R"(","Info":{"Types":{")" + type +
               R"(":{"bases":["RenderDelegate"],"displayName":")" + display + R"(","priority":)" +
               std::to_string(priority) + "}}}}]}";
    }
    std::string root() const { return _root.string(); }

    fs::path _root;
};

}  // namespace

TEST_F(RegistryTest, FindsManifestsInDirAndImmediateSubdirsSortedByPriority) {
    write("", manifest("top", PRD_TEST_OK_PLUGIN, "TopRenderer", "Top", 1));
    write("a", manifest("a", PRD_TEST_OK_PLUGIN, "LowRenderer", "Low", 5));
    write("b", manifest("b", PRD_TEST_OK_PLUGIN, "HighRenderer", "High", 50));
    write("c/deeper",
          manifest("deep", PRD_TEST_OK_PLUGIN, "DeepRenderer", "Deep", 99));  // too deep
    PluginRegistry r({root()});
    auto list = r.renderers();
    ASSERT_EQ(list.size(), 3u);
    EXPECT_EQ(list[0].typeName, "HighRenderer");
    EXPECT_EQ(list[1].typeName, "LowRenderer");
    EXPECT_EQ(list[2].typeName, "TopRenderer");
    EXPECT_EQ(list[0].displayName, "High");
    EXPECT_EQ(list[0].pluginName, "b");
    EXPECT_EQ(list[0].priority, 50);
    EXPECT_EQ(list[0].libraryPath, PRD_TEST_OK_PLUGIN);
    EXPECT_EQ(list[0].plugInfoPath, (_root / "b" / "plugInfo.json").string());
    EXPECT_TRUE(r.diagnostics().empty());
}

TEST_F(RegistryTest, EqualPrioritiesSortByDisplayName) {
    write("x", manifest("x", "x.so", "XRenderer", "Zeta", 3));
    write("y", manifest("y", "y.so", "YRenderer", "Alpha", 3));
    PluginRegistry r({root()});
    auto list = r.renderers();
    ASSERT_EQ(list.size(), 2u);
    EXPECT_EQ(list[0].displayName, "Alpha");
    EXPECT_EQ(list[1].displayName, "Zeta");
}

TEST_F(RegistryTest, RelativeLibraryPathResolvesAgainstTheManifest) {
    write("rel", manifest("rel", "sub/../libfoo.so", "RelRenderer", "Rel", 0));
    PluginRegistry r({root()});
    auto e = r.find("RelRenderer");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->libraryPath, (_root / "rel" / "libfoo.so").string());
}

TEST_F(RegistryTest, FindsByTypeNameThenDisplayNameCaseInsensitiveAndEmptyIsTheBest) {
    write("a", manifest("a", PRD_TEST_OK_PLUGIN, "LowRenderer", "Low", 5));
    write("b", manifest("b", PRD_TEST_OK_PLUGIN, "HighRenderer", "High", 50));
    PluginRegistry r({root()});
    EXPECT_EQ(r.find("LowRenderer")->typeName, "LowRenderer");
    EXPECT_EQ(r.find("low")->typeName, "LowRenderer");
    EXPECT_EQ(r.find("")->typeName, "HighRenderer");
    EXPECT_FALSE(r.find("lowrenderer"));  // type names are exact
    std::string error;
    EXPECT_EQ(r.load("Nope", &error), nullptr);
    EXPECT_EQ(error, "unknown renderer 'Nope'; available: HighRenderer (High), LowRenderer (Low)");
}

TEST_F(RegistryTest, NoPluginsSaysWhereItLooked) {
    PluginRegistry r({root()});
    std::string error;
    EXPECT_EQ(r.load("", &error), nullptr);
    EXPECT_EQ(error,
              "no renderer plugins found (searched " + root() + "; set PRINCIPLED_PLUGIN_PATH)");
}

TEST_F(RegistryTest, MalformedJsonIsReportedWithPathAndReasonAndSkipped) {
    std::string bad = write("broken", R"({"Plugins": [ {"Name": "x", )");
    write("good", manifest("good", PRD_TEST_OK_PLUGIN, "GoodRenderer", "Good", 1));
    PluginRegistry r({root()});
    ASSERT_EQ(r.renderers().size(), 1u);
    EXPECT_EQ(r.renderers()[0].typeName, "GoodRenderer");
    auto d = r.diagnostics();
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0],
              bad +
                  ": malformed JSON: [json.exception.parse_error.101] parse error at line 1, "
                  "column 29: syntax error while parsing object key - unexpected end of input; "
                  "expected string literal");
}

TEST_F(RegistryTest, StructuralProblemsAreReportedExactly) {
    std::string notArray = write("a", R"({"Plugins": {}})");
    std::string noLib = write("b", R"({"Plugins":[{"Name":"NoLib","Type":"library",
        "Info":{"Types":{"T":{"bases":["RenderDelegate"]}}}}]})");
    std::string notLib =
        write("c", R"({"Plugins":[{"Name":"Res","Type":"resource","LibraryPath":"x.so",
        "Info":{"Types":{"T2":{"bases":["RenderDelegate"]}}}}]})");
    std::string badPrio =
        write("d", R"({"Plugins":[{"Name":"P","Type":"library","LibraryPath":"x.so",
        "Info":{"Types":{"T3":{"bases":["RenderDelegate"],"priority":"high"}}}}]})");
    write("e", R"({"Plugins":[{"Name":"Other","Type":"library","LibraryPath":"x.so",
        "Info":{"Types":{"NotARenderer":{"bases":["SomethingElse"]}}}}]})");  // ignored quietly
    PluginRegistry r({root()});
    EXPECT_TRUE(r.renderers().empty());
    EXPECT_THAT(r.diagnostics(),
                ::testing::ElementsAre(
                    notArray + ": expected an object with a \"Plugins\" array",
                    noLib + ": plugin 'NoLib': missing \"LibraryPath\"",
                    notLib + ": plugin 'Res': \"Type\" must be \"library\" for a render delegate",
                    badPrio + ": plugin 'P': type 'T3': \"priority\" must be an integer"));
}

TEST_F(RegistryTest, CommentsAreAllowedAsInUsdPlugInfoFiles) {
    write("c",
          "// a comment\n/* block */\n" + manifest("c", PRD_TEST_OK_PLUGIN, "CRenderer", "C", 0));
    PluginRegistry r({root()});
    EXPECT_EQ(r.renderers().size(), 1u);
    EXPECT_TRUE(r.diagnostics().empty());
}

TEST_F(RegistryTest, FirstDeclarationWinsAcrossSearchPaths) {
    write("first", manifest("one", PRD_TEST_OK_PLUGIN, "SameRenderer", "One", 1));
    std::string second =
        write("second", manifest("two", PRD_TEST_OK_PLUGIN, "SameRenderer", "Two", 9));
    PluginRegistry r({(_root / "first").string(), (_root / "second").string()});
    ASSERT_EQ(r.renderers().size(), 1u);
    EXPECT_EQ(r.renderers()[0].displayName, "One");
    EXPECT_THAT(
        r.diagnostics(),
        ::testing::ElementsAre(
            second + ": plugin 'two': renderer 'SameRenderer' ignored: already declared by " +
            (_root / "first" / "plugInfo.json").string()));
}

TEST_F(RegistryTest, TheSameManifestReachedTwiceIsReadOnce) {
    write("p", manifest("p", PRD_TEST_OK_PLUGIN, "PRenderer", "P", 0));
    PluginRegistry r({root(), (_root / "p").string()});
    EXPECT_EQ(r.renderers().size(), 1u);
    EXPECT_TRUE(r.diagnostics().empty());
}

TEST_F(RegistryTest, SearchPathThatIsNotADirectoryIsReported) {
    PluginRegistry r({(_root / "nope").string()});
    EXPECT_THAT(r.diagnostics(), ::testing::ElementsAre((_root / "nope").string() +
                                                        ": plugin search path is not a directory"));
}

TEST_F(RegistryTest, LoadsAValidPluginOnceAndLazily) {
    write("ok", manifest("ok", PRD_TEST_OK_PLUGIN, "OkRenderer", "Ok", 0));
    PluginRegistry r({root()});
    EXPECT_FALSE(r.isLoaded("OkRenderer"));
    std::string error;
    const PrdRendererApi* api = r.load("OkRenderer", &error);
    ASSERT_NE(api, nullptr) << error;
    EXPECT_EQ(api->abiVersion, PRD_ABI_VERSION);
    EXPECT_TRUE(r.isLoaded("OkRenderer"));
    EXPECT_EQ(r.load("ok", &error), api);  // by display name, same table
}

TEST_F(RegistryTest, MissingLibraryIsAClearError) {
    std::string m =
        write("missing", manifest("m", "doesNotExist.so", "MissingRenderer", "Missing", 0));
    PluginRegistry r({root()});
    std::string lib = (_root / "missing" / "doesNotExist.so").string();
    std::string error;
    EXPECT_EQ(r.load("MissingRenderer", &error), nullptr);
    EXPECT_EQ(error, "renderer 'MissingRenderer' (" + m + "): cannot load plugin library '" + lib +
                         "': " + lib +
                         ": cannot open shared object file: No such file or directory");
    std::string again;
    EXPECT_EQ(r.load("MissingRenderer", &again), nullptr);  // cached, same message
    EXPECT_EQ(again, error);
    EXPECT_FALSE(r.isLoaded("MissingRenderer"));
}

TEST_F(RegistryTest, LibraryWithoutEntryPointIsAClearError) {
    std::string m =
        write("noentry", manifest("n", PRD_TEST_NOENTRY_PLUGIN, "NoEntryRenderer", "NoEntry", 0));
    PluginRegistry r({root()});
    std::string error;
    EXPECT_EQ(r.load("NoEntryRenderer", &error), nullptr);
    EXPECT_EQ(error, "renderer 'NoEntryRenderer' (" + m + "): plugin library '" +
                         std::string(PRD_TEST_NOENTRY_PLUGIN) +
                         "' does not export 'principledRendererPlugin'");
}

TEST_F(RegistryTest, WrongAbiVersionIsRefused) {
    std::string m =
        write("badabi", manifest("b", PRD_TEST_BADABI_PLUGIN, "BadAbiRenderer", "BadAbi", 0));
    PluginRegistry r({root()});
    std::string error;
    EXPECT_EQ(r.load("BadAbiRenderer", &error), nullptr);
    EXPECT_EQ(error, "renderer 'BadAbiRenderer' (" + m + "): plugin library '" +
                         std::string(PRD_TEST_BADABI_PLUGIN) +
                         "' has ABI version 999; this host needs 1");
}

TEST(RegistryDefaults, PluginPathEnvironmentComesFirstThenTheBuiltinFolder) {
    setenv("PRINCIPLED_PLUGIN_PATH", "/tmp/a::/tmp/b", 1);
    auto paths = PluginRegistry::defaultSearchPaths();
    unsetenv("PRINCIPLED_PLUGIN_PATH");
    ASSERT_GE(paths.size(), 3u);
    EXPECT_EQ(paths[0], "/tmp/a");
    EXPECT_EQ(paths[1], "/tmp/b");
    // The test binary lives in build/bin: the built-in folder is build/lib/principled/plugins.
    EXPECT_EQ(paths[2], fs::weakly_canonical(fs::path(PRINCIPLED_BINARY_DIR) / "lib" /
                                             "principled" / "plugins")
                            .string());
}

TEST(RegistryDefaults, BuiltinFolderHoldsTheEmbreePlugin) {
    PluginRegistry r(PluginRegistry::builtinPluginDirs());
    auto e = r.find("PrincipledEmbreeRenderer");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->displayName, "Embree");
    EXPECT_EQ(e->pluginName, "hdPrincipled");
    EXPECT_EQ(e->priority, 99);
}

TEST_F(RegistryTest, DescribePluginsListsRenderersSearchPathAndWarnings) {
    write("b", manifest("hdPrincipled", "/x/lib.so", "PrincipledEmbreeRenderer", "Embree", 99));
    std::string bad = write("c", "{");
    PluginRegistry r({root()});
    EXPECT_EQ(
        describePlugins(r),
        "hdPrincipled: PrincipledEmbreeRenderer \"Embree\" priority 99\n    /x/lib.so\n"
        "search path:\n    " +
            root() +
            "\n"
            "warning: " +
            bad +
            ": malformed JSON: [json.exception.parse_error.101] parse error at "
            "line 1, column 2: syntax error while parsing object key - unexpected end of input; "
            "expected string literal\n");
}
