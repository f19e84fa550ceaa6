// Distributed rendering as a user runs it: `mpirun -np N principled render` against the
// single-process render of the same samples, checkpoints and --resume, refused checkpoints,
// failing ranks and --frames. Images are tiny and sample counts low so the suite stays fast.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Result {
    int status;
    std::string output;
};

Result shell(const std::string& cmd) {
    Result r{-1, ""};
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
    int s = pclose(p);
    r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    return r;
}

std::string binary() { return std::string(PRINCIPLED_BINARY_DIR) + "/bin/principled"; }
std::string scene() { return std::string(PRINCIPLED_SOURCE_DIR) + "/tests/distributed/scenes/anim.usda"; }

// Common render arguments: every AOV kind the merge treats differently.
const std::string kArgs = " --res 32x24 --seed 3 --aov primId,instanceId,depth,normal,albedo,sampleCount,variance -q";

std::string mpirun(int np) {
    // Root needs the two OMPI_ALLOW_* variables; -np 4 on 2 cores needs --oversubscribe.
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader " +
           std::string(PRINCIPLED_MPIEXEC) + " --oversubscribe -np " + std::to_string(np) + " ";
}

fs::path dir() {
    fs::path d = fs::temp_directory_path() / ("principled_distributed_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
}

// Removes this process's scratch directory after its tests.
class ScratchCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir(), ec);
    }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

using Image = std::map<std::string, std::vector<float>>;  // channel name -> pixels

Image readExr(const fs::path& path) {
    Image img;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return img;
    const auto& spec = in->spec();
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    size_t n = size_t(spec.width) * spec.height;
    for (int c = 0; c < spec.nchannels; ++c) {
        auto& v = img[spec.channelnames[c]];
        for (size_t p = 0; p < n; ++p) v.push_back(px[p * spec.nchannels + c]);
    }
    return img;
}

bool exact(const std::string& channel) {
    // First-hit AOVs and counts are copied, never summed: identical whatever the rank count.
    for (const char* prefix : {"primId", "instanceId", "depth", "normal", "sampleCount"})
        if (channel.rfind(prefix, 0) == 0) return true;
    return false;
}

// The documented bound (docs/distributed.md): a mean of n samples summed in double in another
// grouping differs by at most 2(n-1)*2^-53 of the mean of |sample|, then one float rounding:
// |a - b| <= (2^-23 + 2(n-1)*2^-53) * max(|a|, |b|) for the non-negative radiance AOVs.
void expectEquivalent(const Image& ref, const Image& got, int spp, const std::string& what) {
    ASSERT_FALSE(ref.empty()) << what;
    ASSERT_EQ(ref.size(), got.size()) << what;
    double bound = std::ldexp(1.0, -23) + 2.0 * (spp - 1) * std::ldexp(1.0, -53);
    for (const auto& [name, a] : ref) {
        auto it = got.find(name);
        ASSERT_NE(it, got.end()) << what << ": channel " << name;
        const auto& b = it->second;
        ASSERT_EQ(a.size(), b.size());
        int bad = 0;
        for (size_t p = 0; p < a.size(); ++p) {
            double tol = exact(name) ? 0.0
                         : name.rfind("variance", 0) == 0
                             ? 1e-5 * std::max(std::fabs(a[p]), std::fabs(b[p])) + 1e-9  // sum-of-squares cancellation
                             : bound * std::max(std::fabs(a[p]), std::fabs(b[p]));
            if (!(std::fabs(double(a[p]) - double(b[p])) <= tol) && bad++ < 3)
                ADD_FAILURE() << what << ": channel " << name << " pixel " << p << ": " << a[p] << " vs " << b[p];
        }
        EXPECT_EQ(bad, 0) << what << ": channel " << name;
    }
}

bool identical(const Image& a, const Image& b) { return !a.empty() && a == b; }

std::string render(const std::string& extra, const fs::path& out, const std::string& usda = scene()) {
    return binary() + " render " + usda + kArgs + extra + " -o " + out.string();
}

}  // namespace

#if PRINCIPLED_TEST_MPI

class MpiRanks : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(MpiRanks, MatchSingleProcessWithinTheSummationBound) {
    auto [np, spp] = GetParam();
    fs::path d = dir();
    std::string sppArg = " --spp " + std::to_string(spp);
    fs::path ref = d / ("single" + std::to_string(spp) + ".exr"), out = d / ("np" + std::to_string(np) + ".exr");
    Result single = shell(render(sppArg, ref));
    ASSERT_EQ(single.status, 0) << single.output;
    Result mpi = shell(mpirun(np) + render(sppArg, out));
    ASSERT_EQ(mpi.status, 0) << mpi.output;
    expectEquivalent(readExr(ref), readExr(out), spp, "np " + std::to_string(np));
}

// np 4 with 3 spp leaves rank 3 an empty sample range.
INSTANTIATE_TEST_SUITE_P(Np, MpiRanks,
                         ::testing::Values(std::pair{1, 8}, std::pair{2, 8}, std::pair{4, 8}, std::pair{4, 3}));

TEST(Mpi, KilledAfterCheckpointResumesToTheUninterruptedImage) {
    fs::path d = dir() / "resume2";
    fs::remove_all(d);
    std::string args = " --spp 8 --checkpoint-every 2";
    Result full = shell(mpirun(2) + render(args, d / "full.exr"));
    ASSERT_EQ(full.status, 0) << full.output;
    EXPECT_FALSE(fs::exists(d / "full.exr.ckpt")) << "checkpoints are removed after success";

    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + mpirun(2) + " -x PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT " +
                          render(args, d / "out.exr"));
    EXPECT_NE(killed.status, 0) << killed.output;
    EXPECT_FALSE(fs::exists(d / "out.exr")) << "no output from a killed job";
    ASSERT_TRUE(fs::exists(d / "out.exr.ckpt")) << killed.output;

    Result resumed = shell(mpirun(2) + render(args + " --resume", d / "out.exr"));
    ASSERT_EQ(resumed.status, 0) << resumed.output;
    EXPECT_TRUE(identical(readExr(d / "full.exr"), readExr(d / "out.exr")));
    for (const auto& e : fs::directory_iterator(d))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(Mpi, FailingRankEndsTheJobNamingIt) {
    fs::path d = dir() / "failing";
    fs::remove_all(d);
    fs::create_directories(d);
    // MPMD: rank 1 gets a scene its node cannot read.
    std::string good = render(" --spp 4", d / "out.exr");
    std::string bad = binary() + " render " + (d / "missing.usda").string() + kArgs + " --spp 4 -o " + (d / "out.exr").string();
    Result r = shell(mpirun(1) + good + " : -np 1 " + bad);
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("rank 1 of 2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("cannot read the scene file"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out.exr"));

    // A killed rank: mpirun names it and the signal.
    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + mpirun(2) + " -x PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT " +
                          render(" --spp 8 --checkpoint-every 1", d / "out.exr"));
    EXPECT_NE(killed.status, 0) << killed.output;
    EXPECT_NE(killed.output.find("rank"), std::string::npos) << killed.output;
    EXPECT_FALSE(fs::exists(d / "out.exr"));
}

TEST(Mpi, FramesGoToRanksWholeAndMatchSingleProcessBitForBit) {
    fs::path d = dir() / "frames";
    fs::remove_all(d);
    Result r = shell(mpirun(2) + render(" --spp 4 --frames 0:3", d / "anim.exr"));
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* f : {"anim.0000.exr", "anim.0001.exr", "anim.0002.exr", "anim.0003.exr"})
        EXPECT_TRUE(fs::exists(d / f)) << f;
    EXPECT_FALSE(identical(readExr(d / "anim.0000.exr"), readExr(d / "anim.0003.exr"))) << "the ball moves";
    Result one = shell(render(" --spp 4 --frames 3:3", d / "one.exr"));
    ASSERT_EQ(one.status, 0) << one.output;
    EXPECT_TRUE(identical(readExr(d / "anim.0003.exr"), readExr(d / "one.0003.exr")));
}

TEST(Mpi, FewerFramesThanRanksSplitEachFrame) {
    fs::path d = dir() / "fewframes";
    fs::remove_all(d);
    Result r = shell(mpirun(4) + render(" --spp 8 --frames 0:1", d / "mpi.exr"));
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_EQ(shell(render(" --spp 8 --frames 0:1", d / "one.exr")).status, 0);
    for (const char* f : {"0000", "0001"})
        expectEquivalent(readExr(d / ("one." + std::string(f) + ".exr")), readExr(d / ("mpi." + std::string(f) + ".exr")), 8,
                         std::string("frame ") + f);
}

#endif  // PRINCIPLED_TEST_MPI

TEST(Checkpoint, ResumeEqualsUninterruptedSingleProcess) {
    fs::path d = dir() / "resume1";
    fs::remove_all(d);
    std::string args = " --spp 8 --checkpoint-every 2";
    ASSERT_EQ(shell(render(" --spp 8", d / "plain.exr")).status, 0);
    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + render(args, d / "out.exr"));
    EXPECT_NE(killed.status, 0) << killed.output;
    EXPECT_FALSE(fs::exists(d / "out.exr"));
    ASSERT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << killed.output;
    Result resumed = shell(render(args + " --resume", d / "out.exr"));
    ASSERT_EQ(resumed.status, 0) << resumed.output;
    EXPECT_TRUE(identical(readExr(d / "plain.exr"), readExr(d / "out.exr")));
}

TEST(Checkpoint, CausticSceneResumesToTheUninterruptedImage) {
    // Light-traced caustics: the light paths' sequence, their budget and the light-traced
    // share's statistics (in the variance AOV) must continue where the checkpoint left them.
    const std::string caustic = std::string(PRINCIPLED_SOURCE_DIR) + "/tests/distributed/scenes/caustic.usda";
    fs::path d = dir() / "resumeCaustic";
    fs::remove_all(d);
    std::string args = " --spp 40 --checkpoint-every 2";
    ASSERT_EQ(shell(render(" --spp 40", d / "plain.exr", caustic)).status, 0);
    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + render(args, d / "out.exr", caustic));
    EXPECT_NE(killed.status, 0) << killed.output;
    ASSERT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << killed.output;
    Result resumed = shell(render(args + " --resume", d / "out.exr", caustic));
    ASSERT_EQ(resumed.status, 0) << resumed.output;
    EXPECT_TRUE(identical(readExr(d / "plain.exr"), readExr(d / "out.exr")));
}

TEST(Checkpoint, ForeignCheckpointIsRefused) {
    fs::path d = dir() / "foreign";
    fs::remove_all(d);
    std::string args = " --spp 8 --checkpoint-every 2";
    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + render(args, d / "out.exr"));
    ASSERT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << killed.output;

    Result seed = shell(render(args + " --resume --max-depth 3", d / "out.exr"));
    EXPECT_EQ(seed.status, 1) << seed.output;
    EXPECT_NE(seed.output.find("refusing to resume"), std::string::npos) << seed.output;
    EXPECT_NE(seed.output.find("maxDepth: 8 there, 3 here"), std::string::npos) << seed.output;

    fs::path other = d / "other.usda";
    std::ifstream in(scene());
    std::ofstream(other) << in.rdbuf() << "\n# edited\n";
    Result sceneEdit = shell(binary() + " render " + other.string() + kArgs + args + " --resume -o " + (d / "out.exr").string());
    EXPECT_EQ(sceneEdit.status, 1) << sceneEdit.output;
    EXPECT_NE(sceneEdit.output.find("another scene"), std::string::npos) << sceneEdit.output;
    EXPECT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << "a refused checkpoint is left alone";
    EXPECT_FALSE(fs::exists(d / "out.exr"));
}

TEST(Checkpoint, ChangedSublayerOrTextureIsRefusedNamingTheFile) {
    // The composed stage is the scene: a checkpoint is refused when any layer it read changed
    // (the root layer was the only one hashed) or a file its attributes name (a texture).
    fs::path d = dir() / "layers";
    fs::remove_all(d);
    fs::create_directories(d);
    ASSERT_EQ(shell(binary() + " render -o " + (d / "sky.png").string() + " --res 8x4 --spp 1 -q").status, 0);
    std::ofstream(d / "top.usda") << "#usda 1.0\n(\n    subLayers = [@sub.usda@]\n)\n";
    auto writeSub = [&](const char* color) {
        std::ofstream(d / "sub.usda") << "#usda 1.0\ndef Sphere \"S\" { color3f[] primvars:displayColor = [" << color
                                      << "] }\ndef DomeLight \"Sky\" { asset inputs:texture:file = @sky.png@ }\n";
    };
    writeSub("(0.8, 0.2, 0.2)");
    const std::string top = (d / "top.usda").string(), args = " --spp 8 --checkpoint-every 2";
    Result killed = shell("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT=1 " + render(args, d / "out.exr", top));
    ASSERT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << killed.output;

    writeSub("(0.2, 0.2, 0.8)");
    Result sub = shell(render(args + " --resume", d / "out.exr", top));
    EXPECT_EQ(sub.status, 1) << sub.output;
    EXPECT_NE(sub.output.find("refusing to resume"), std::string::npos) << sub.output;
    EXPECT_NE(sub.output.find((d / "sub.usda").string() + " changed"), std::string::npos) << sub.output;

    writeSub("(0.8, 0.2, 0.2)");  // the same bytes again: only the texture differs now
    ASSERT_EQ(shell(binary() + " render -o " + (d / "sky.png").string() + " --res 8x4 --spp 1 --seed 9 -q").status, 0);
    Result tex = shell(render(args + " --resume", d / "out.exr", top));
    EXPECT_EQ(tex.status, 1) << tex.output;
    EXPECT_NE(tex.output.find((d / "sky.png").string() + " changed"), std::string::npos) << tex.output;
    EXPECT_TRUE(fs::exists(d / "out.exr.ckpt" / "rank0.exr")) << "a refused checkpoint is left alone";
    EXPECT_FALSE(fs::exists(d / "out.exr"));
}

TEST(Checkpoint, AdaptiveSamplingIsRefusedHoweverItIsSet) {
    // --set noiseThreshold=... turned adaptive sampling on past the refusal of --noise-threshold:
    // an interrupted and resumed render then differed from the uninterrupted one.
    fs::path d = dir() / "adaptive";
    fs::remove_all(d);
    for (const char* how : {" --noise-threshold 0.05", " --set noiseThreshold=0.05"}) {
        Result r = shell(render(std::string(" --spp 8 --checkpoint-every 2") + how, d / "out.exr"));
        EXPECT_EQ(r.status, 1) << how << "\n" << r.output;
        EXPECT_NE(r.output.find("cannot be combined"), std::string::npos) << how << "\n" << r.output;
        EXPECT_FALSE(fs::exists(d / "out.exr")) << how;
    }
    Result off = shell(render(" --spp 2 --checkpoint-every 2 --set noiseThreshold=0", d / "out.exr"));
    EXPECT_EQ(off.status, 0) << off.output;
}

TEST(Checkpoint, StatsAreWrittenAndTimeLimitIsRefused) {
    // With --checkpoint-every, --frames or --resume, --stats wrote nothing and --time-limit was
    // ignored, both without a word (exit 0).
    fs::path d = dir() / "statsLimit";
    fs::remove_all(d);
    fs::create_directories(d);
    Result ck = shell(render(" --spp 4 --checkpoint-every 2 --stats " + (d / "ck.json").string(), d / "ck.exr"));
    ASSERT_EQ(ck.status, 0) << ck.output;
    std::ifstream in(d / "ck.json");
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const char* key : {"\"samplesPerPixel\": 4", "\"width\": 32", "\"renderWallSeconds\"", "\"checkpointsWritten\": 2"})
        EXPECT_NE(json.find(key), std::string::npos) << key << " missing from " << json;
    Result frames = shell(render(" --spp 2 --frames 0:1 --stats " + (d / "fr.json").string(), d / "fr.exr"));
    ASSERT_EQ(frames.status, 0) << frames.output;
    EXPECT_TRUE(fs::exists(d / "fr.json"));
    for (const char* how : {" --checkpoint-every 2", " --frames 0:1", " --resume"}) {
        Result limit = shell(render(std::string(" --spp 4 --time-limit 0.5") + how, d / "tl.exr"));
        EXPECT_EQ(limit.status, 1) << how << "\n" << limit.output;
        EXPECT_NE(limit.output.find("--time-limit cannot be combined"), std::string::npos) << how << "\n" << limit.output;
        EXPECT_FALSE(fs::exists(d / "tl.exr")) << how;
    }
}
