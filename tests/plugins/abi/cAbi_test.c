/* SPDX-License-Identifier: Apache-2.0 */
/* A DCC-style host in pure C: finds the Embree plugin through PRINCIPLED_PLUGIN_PATH, renders a
 * tiny USDA scene through principled_c.h only, and checks that errors come back as status codes
 * with messages. Compiled as C11; exits non-zero on the first failed check. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plugins/abi/principled_c.h"

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
            ++failures;                                                              \
        }                                                                            \
    } while (0)

#define CHECK_STATUS(call, expected)                                                           \
    do {                                                                                       \
        PrdStatus s_ = (call);                                                                 \
        if (s_ != (expected)) {                                                                \
            fprintf(stderr, "%s:%d: %s returned %s, expected %s\n", __FILE__, __LINE__, #call, \
                    prdStatusName(s_), prdStatusName(expected));                               \
            ++failures;                                                                        \
        }                                                                                      \
    } while (0)

#define CHECK_CONTAINS(text, part)                                                     \
    do {                                                                               \
        const char* t_ = (text);                                                       \
        if (!t_ || !strstr(t_, (part))) {                                              \
            fprintf(stderr, "%s:%d: '%s' does not contain '%s'\n", __FILE__, __LINE__, \
                    t_ ? t_ : "(null)", (part));                                       \
            ++failures;                                                                \
        }                                                                              \
    } while (0)

static const char* kScene =
    "#usda 1.0\n"
    "(\n    upAxis = \"Y\"\n)\n"
    "def Xform \"World\"\n{\n"
    "    def Mesh \"Plane\" (prepend apiSchemas = [\"MaterialBindingAPI\"])\n    {\n"
    "        int[] faceVertexCounts = [4]\n"
    "        int[] faceVertexIndices = [0, 1, 2, 3]\n"
    "        point3f[] points = [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)]\n"
    "        rel material:binding = </World/Mat>\n    }\n"
    "    def Material \"Mat\"\n    {\n"
    "        token outputs:surface.connect = </World/Mat/S.outputs:surface>\n"
    "        def Shader \"S\"\n        {\n"
    "            uniform token info:id = \"UsdPreviewSurface\"\n"
    "            color3f inputs:diffuseColor = (0.5, 0.5, 0.5)\n"
    "            token outputs:surface\n        }\n    }\n"
    "    def DistantLight \"Sun\"\n    {\n        float inputs:intensity = 3\n    }\n"
    "    def Camera \"Cam\"\n    {\n"
    "        double3 xformOp:translate = (0, 0, 10)\n"
    "        uniform token[] xformOpOrder = [\"xformOp:translate\"]\n    }\n"
    "}\n";

int main(void) {
    PrdDelegate* d = NULL;
    PrdRendererInfo info;
    PrdBufferView view;
    PrdAovInfo aov;
    int i, count = 0, converged = 0, passes = 0, found = 0, nonzero = 0, finite = 1;
    const char* plugin_path = getenv("PRINCIPLED_PLUGIN_PATH");

    CHECK(prdAbiVersion() == PRD_ABI_VERSION);
    CHECK(plugin_path != NULL);

    /* The registry finds the Embree plugin. */
    count = prdRendererCount();
    CHECK(count >= 1);
    for (i = 0; i < count; ++i) {
        CHECK_STATUS(prdRendererInfo(i, &info), PRD_OK);
        if (strcmp(info.typeName, "PrincipledEmbreeRenderer") == 0) {
            found = 1;
            CHECK(strcmp(info.displayName, "Embree") == 0);
            CHECK(info.priority == 99);
            CHECK(plugin_path && strncmp(info.libraryPath, plugin_path, strlen(plugin_path)) == 0);
        }
    }
    CHECK(found);
    CHECK(strcmp(prdRegistryDiagnostics(), "") == 0);

    /* Unknown renderer: a status and a message, no handle. */
    CHECK_STATUS(prdCreateDelegate("NoSuchRenderer", &d), PRD_ERROR_NOT_FOUND);
    CHECK(d == NULL);
    CHECK_CONTAINS(
        prdLastError(NULL),
        "unknown renderer 'NoSuchRenderer'; available: PrincipledEmbreeRenderer (Embree)");

    /* Null handles and null arguments. */
    CHECK_STATUS(prdOpenStageString(NULL, kScene, "scene"), PRD_ERROR_NULL_HANDLE);
    CHECK_CONTAINS(prdLastError(NULL), "prdOpenStageString: delegate is NULL");
    CHECK_STATUS(prdRenderPass(NULL, &converged), PRD_ERROR_NULL_HANDLE);
    CHECK_STATUS(prdMapAov(NULL, "color", &view), PRD_ERROR_NULL_HANDLE);
    CHECK_STATUS(prdCreateDelegate("Embree", NULL), PRD_ERROR_INVALID_ARGUMENT);
    prdDestroyDelegate(NULL); /* a no-op */

    /* Create by display name through the registry. */
    CHECK_STATUS(prdCreateDelegate("Embree", &d), PRD_OK);
    CHECK(d != NULL);
    if (!d) return 1;
    CHECK(strcmp(prdLastError(d), "") == 0);

    /* Rendering before a stage is open. */
    CHECK_STATUS(prdRenderPass(d, &converged), PRD_ERROR_NO_STAGE);
    CHECK_CONTAINS(prdLastError(d), "needs an open stage");

    /* Bad file, bad text. */
    CHECK_STATUS(prdOpenStageFile(d, "/no/such/scene.usda"), PRD_ERROR_IO);
    CHECK_CONTAINS(prdLastError(d),
                   "prdOpenStageFile: cannot open '/no/such/scene.usda': no such file");
    CHECK_STATUS(prdOpenStageString(d, "#usda 1.0\ndef Xform \"A\" {\n", "broken.usda"),
                 PRD_ERROR_IO);
    CHECK_CONTAINS(prdLastError(d), "broken.usda:");
    CHECK_STATUS(prdOpenStageFile(d, "/tmp"), PRD_ERROR_IO);
    CHECK_CONTAINS(prdLastError(d), "prdOpenStageFile: cannot open '/tmp': not a regular file");
    CHECK_STATUS(prdOpenStageFile(d, NULL), PRD_ERROR_INVALID_ARGUMENT);
    CHECK_CONTAINS(prdLastError(d), "prdOpenStageFile: path is NULL");

    /* Unknown AOV. */
    CHECK_STATUS(prdBindAov(d, "bogus"), PRD_ERROR_NOT_FOUND);
    CHECK_CONTAINS(prdLastError(d), "prdBindAov: unknown AOV 'bogus'; this renderer has: color");
    CHECK_STATUS(prdAovDescribe(d, "color", &aov), PRD_OK);
    CHECK(aov.format == PRD_FORMAT_FLOAT32_VEC4 && aov.channels == 4 && aov.multiSampled == 1);

    /* Render a tiny image. */
    CHECK_STATUS(prdSetResolution(d, 24, 16), PRD_OK);
    CHECK_STATUS(prdSetSettingInt(d, "convergedSamplesPerPixel", 4), PRD_OK);
    CHECK_STATUS(prdSetSettingString(d, "convergedSamplesPerPixel", "4"),
                 PRD_ERROR_INVALID_ARGUMENT);
    CHECK_CONTAINS(
        prdLastError(d),
        "render setting 'convergedSamplesPerPixel' is an int; set it with prdSetSettingInt");
    CHECK_STATUS(prdBindAov(d, "color"), PRD_OK);
    CHECK_STATUS(prdOpenStageString(d, kScene, "tiny.usda"), PRD_OK);
    while (!converged && passes < 100) {
        CHECK_STATUS(prdRenderPass(d, &converged), PRD_OK);
        ++passes;
    }
    CHECK(converged == 1);
    CHECK_STATUS(prdMapAov(d, "color", &view), PRD_OK);
    CHECK(view.data != NULL && view.width == 24 && view.height == 16 && view.channels == 4);
    CHECK(view.format == PRD_FORMAT_FLOAT32_VEC4 && view.converged == 1);
    if (view.data) {
        const float* px = (const float*)view.data;
        for (i = 0; i < view.width * view.height * view.channels; ++i) {
            if (!isfinite(px[i])) finite = 0;
            if (px[i] != 0.0f) ++nonzero;
        }
    }
    CHECK(finite);
    CHECK(nonzero > 0);

    /* Mapping something not bound, stats. */
    CHECK_STATUS(prdMapAov(d, "depth", &view), PRD_ERROR_NOT_BOUND);
    CHECK_CONTAINS(prdLastError(d), "AOV 'depth' is not bound");
    CHECK_STATUS(prdStatCount(d, &count), PRD_OK);
    CHECK(count > 0);
    {
        const char* key = NULL;
        double value = 0.0, rays = -1.0;
        for (i = 0; i < count; ++i) {
            CHECK_STATUS(prdStat(d, i, &key, &value), PRD_OK);
            if (key && strcmp(key, "rays") == 0) rays = value;
        }
        CHECK(rays > 0.0);
    }

    /* The same kind of scene from host data, as a DCC would hand it over. */
    {
        PrdSceneBuilder* b = NULL;
        const float pts[] = {-5, -5, 0, 5, -5, 0, 5, 5, 0, -5, 5, 0};
        const int counts[] = {4}, indices[] = {0, 1, 2, 3};
        const double grey[3] = {0.5, 0.5, 0.5}, intensity = 3.0;
        const double cam[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 10, 1};
        CHECK_STATUS(prdSceneBuilderCreate(&b), PRD_OK);
        CHECK_STATUS(prdSceneAddMesh(b, "/Host/Quad", pts, 4, counts, 1, indices, 4), PRD_OK);
        CHECK_STATUS(prdSceneAddMaterial(b, "/Host/Grey"), PRD_OK);
        CHECK_STATUS(prdSceneSetMaterialInput(b, "/Host/Grey", "diffuseColor", grey, 3), PRD_OK);
        CHECK_STATUS(prdSceneBindMaterial(b, "/Host/Quad", "/Host/Grey"), PRD_OK);
        CHECK_STATUS(prdSceneAddPrim(b, "/Host/Sun", "DistantLight"), PRD_OK);
        CHECK_STATUS(
            prdSceneSetAttribute(b, "/Host/Sun", "float", "inputs:intensity", &intensity, 1, NULL),
            PRD_OK);
        CHECK_STATUS(prdSceneAddPrim(b, "/Host/Cam", "Camera"), PRD_OK);
        CHECK_STATUS(prdSceneSetTransform(b, "/Host/Cam", cam), PRD_OK);
        CHECK_STATUS(prdSceneAddMesh(b, "relative/path", pts, 4, counts, 1, indices, 4),
                     PRD_ERROR_INVALID_ARGUMENT);
        CHECK_CONTAINS(prdLastError(NULL), "must be absolute");
        CHECK_STATUS(prdOpenStageFromBuilder(d, b), PRD_OK);
        converged = 0;
        passes = 0;
        while (!converged && passes < 100) {
            CHECK_STATUS(prdRenderPass(d, &converged), PRD_OK);
            ++passes;
        }
        CHECK_STATUS(prdMapAov(d, "color", &view), PRD_OK);
        nonzero = 0;
        if (view.data) {
            const float* px = (const float*)view.data;
            for (i = 0; i < view.width * view.height * view.channels; ++i)
                if (isfinite(px[i]) && px[i] > 0.0f) ++nonzero;
        }
        CHECK(nonzero > 0);
        prdSceneBuilderDestroy(b);
    }

    prdDestroyDelegate(d);
    if (failures) {
        fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    printf("C ABI host: all checks passed (%d passes)\n", passes);
    return 0;
}
