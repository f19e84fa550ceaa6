// SPDX-License-Identifier: Apache-2.0
#include "tools/infoCommand.h"

#include <cstdio>
#include <map>
#include <memory>

#include "delegate/renderDelegate.h"
#include "plugins/renderSession.h"
#include "scene_adapter/usda/error.h"
#include "scene_adapter/usda/stage.h"
#include "tools/defaultScene.h"

namespace principled::tools {

namespace {

int runInfo(const std::string& scene, const std::string& camera, int refineLevel) {
    host::SessionOptions o;
    o.width = o.height = 0;  // as `principled render` without --res: the stage's RenderSettings, else 640x360
    o.samplesPerPixel = 1;
    o.camera = camera;
    o.refineLevel = refineLevel;
    std::unique_ptr<host::RenderSession> s;
    try {
        s = scene.empty() ? host::RenderSession::openString(kDefaultSceneUsda, "<default scene>", o)
                          : host::RenderSession::openFile(scene, o);
    } catch (const usd::Error& e) {
        std::fprintf(stderr, "principled: error: %s\n", e.what());
        return 1;
    } catch (const host::UserError& e) {
        std::fprintf(stderr, "principled: error: %s\n", e.what());
        return 1;
    }
    const usd::Stage& stage = s->stage();
    std::map<std::string, int> byType;
    size_t nativeInstances = 0;  // instanceable prims (native instancing)
    for (const usd::Prim* p : stage.traverse()) {
        ++byType[p->typeName().empty() ? "(untyped)" : p->typeName()];
        nativeInstances += p->isInstance();
    }
    std::printf("stage: %s\n", scene.empty() ? "<default scene>" : scene.c_str());
    std::printf("  layers: %zu, upAxis %s, metersPerUnit %g", stage.layerFiles().size(),
                stage.upAxis().c_str(), stage.metersPerUnit());
    if (stage.hasTimeCodes())
        std::printf(", time codes %g..%g at %g/s", stage.startTimeCode(), stage.endTimeCode(),
                    stage.timeCodesPerSecond());
    std::printf("\nprims by type:\n");
    for (const auto& [type, n] : byType) std::printf("  %-20s %d\n", type.c_str(), n);
    auto sum = s->delegate()->summary();
    std::printf("geometry: %zu meshes (%zu triangles after refinement), %zu spheres, %zu instances",
                sum.meshes, sum.triangles, sum.spheres, sum.instances);
    // The delegate's instancers include those it makes for instanceable prims: point
    // instancers are the stage's PointInstancer prims.
    const size_t pointInstancers = byType.count("PointInstancer") ? size_t(byType["PointInstancer"]) : 0;
    if (pointInstancers || nativeInstances) {
        std::printf(" (");
        if (pointInstancers) std::printf("%zu point instancers%s", pointInstancers, nativeInstances ? ", " : "");
        if (nativeInstances) std::printf("%zu instanceable prims", nativeInstances);
        std::printf(")");
    }
    if (sum.points) std::printf(", %zu points", sum.points);
    if (sum.curvePrims) std::printf(", %zu curves prims (%zu segments)", sum.curvePrims, sum.curveSegments);
    std::printf("\nmaterials: %zu\n", sum.materialLobes.size());
    for (const auto& [path, lobes] : sum.materialLobes) std::printf("  %s: %s\n", path.c_str(), lobes.c_str());
    std::printf("lights:");
    if (sum.lightsByKind.empty()) std::printf(" none (a white dome lights the render)");
    for (const auto& [kind, n] : sum.lightsByKind) std::printf(" %zu %s", n, kind.c_str());
    std::printf("\ncamera: %s\n", s->cameraPath().c_str());
    auto warnings = s->takeWarnings();
    std::printf("warnings: %zu\n", warnings.size());
    for (const auto& w : warnings) std::printf("  %s\n", w.c_str());
    return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int* exitCode) {
    auto scene = std::make_shared<std::string>();
    auto camera = std::make_shared<std::string>();
    auto level = std::make_shared<int>(-1);
    auto* cmd = app.add_subcommand("info", "Print what a stage holds: prims, geometry, materials, lights, warnings");
    cmd->add_option("scene", *scene, "USDA file; omitted: the built-in default scene");
    cmd->add_option("--camera", *camera, "Camera prim (adaptive subdivision is measured from it)");
    cmd->add_option("--refine-level", *level, "Subdivision level; -1 = adaptive")->check(CLI::Range(-1, 8));
    cmd->callback([=] { *exitCode = runInfo(*scene, *camera, *level); });
}

}  // namespace principled::tools
