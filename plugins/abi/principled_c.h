/* SPDX-License-Identifier: Apache-2.0 */
/* principled_c.h: the C ABI a host (a DCC viewport, a Python/ctypes binding, a test) uses to
 * find, create and drive a principled render delegate. Pure C89-compatible declarations: opaque
 * handles, status codes, plain structs of C types, no C++ types and no exceptions cross it.
 *
 * Rules (docs/plugins.md has the long form):
 *  - Every call returns a PrdStatus (or a plain value for the few queries that cannot fail).
 *    On failure, prdLastError(handle) holds a human-readable message until the next call on
 *    that handle; calls that have no handle yet (create) or got a NULL handle report through
 *    prdLastError(NULL), which is thread-local.
 *  - Strings passed in are UTF-8 and only read during the call. Strings and buffers returned
 *    stay owned by the library; their lifetime is stated per call.
 *  - A handle is used by one thread at a time; different handles are independent.
 *  - PRD_ABI_VERSION changes when a declaration changes incompatibly; calls are only ever
 *    added at the end of the plugin table (principled_plugin.h), which bumps PRD_ABI_MINOR.
 */
#ifndef PRINCIPLED_C_H
#define PRINCIPLED_C_H

#include <stddef.h>
#include <stdint.h>

#include "principled_plugin.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define PRD_API __attribute__((visibility("default")))
#else
#define PRD_API
#endif

/** A render delegate instance: one renderer, at most one open stage, its AOV buffers. */
typedef struct PrdDelegate PrdDelegate;

/* ---- Library and registry ------------------------------------------------------------ */

/** PRD_ABI_VERSION of the library actually loaded (compare with the header's). */
PRD_API uint32_t prdAbiVersion(void);
/** A static name for a status ("PRD_ERROR_NOT_FOUND"). */
PRD_API const char* prdStatusName(PrdStatus status);
/** The message of the last failed call on `delegate`, or "" after a successful call. With
 *  NULL: the last failure of this thread among calls that had no valid handle. Valid until the
 *  next call on the same handle (or, for NULL, on this thread). Never NULL. */
PRD_API const char* prdLastError(const PrdDelegate* delegate);

/** Renderers found by the plugin registry (PRINCIPLED_PLUGIN_PATH, then the built-in plugin
 *  folder), highest priority first. Scans once, on first use. */
PRD_API int prdRendererCount(void);
/** Fills *info for renderer `index` (0-based). Strings live as long as the process. */
PRD_API PrdStatus prdRendererInfo(int index, PrdRendererInfo* info);
/** Problems the registry found (malformed plugInfo.json, ...), one per line; "" if none. */
PRD_API const char* prdRegistryDiagnostics(void);

/* ---- Create / destroy ---------------------------------------------------------------- */

/** Creates a delegate of the renderer `name` (type name or display name, e.g.
 *  "PrincipledEmbreeRenderer" or "Embree"; NULL or "" = the highest-priority renderer),
 *  loading its plugin library on first use. */
PRD_API PrdStatus prdCreateDelegate(const char* name, PrdDelegate** out);
/** Creates a delegate directly from a plugin table the host linked in or resolved itself
 *  (no registry). `typeName` is passed to the table's create. */
PRD_API PrdStatus prdCreateDelegateFromApi(const PrdRendererApi* api, const char* typeName,
                                           PrdDelegate** out);
/** Destroys a delegate (NULL is a no-op). Invalidates every pointer obtained from it. */
PRD_API void prdDestroyDelegate(PrdDelegate* delegate);

/* ---- Scene --------------------------------------------------------------------------- */

/** Opens a .usda file and populates the render index from it (replacing any open stage;
 *  settings, camera path, resolution and AOV bindings are kept). */
PRD_API PrdStatus prdOpenStageFile(PrdDelegate* delegate, const char* path);
/** Same from USDA text; `displayName` (may be NULL) names it in messages. */
PRD_API PrdStatus prdOpenStageString(PrdDelegate* delegate, const char* usdaText,
                                     const char* displayName);

/** Edits attribute `attribute` of prim `primPath` and marks the dirty bits the edit implies
 *  (material input -> material params, light input -> light params, points -> points,
 *  primvars -> primvar, camera -> camera params). `values` holds `count` numbers: 1 for a
 *  scalar, 3 for a color3f/float3, 16 for a matrix, 3*N for point3f[N]; the authored type of
 *  the attribute decides the stored type. PRD_ERROR_UNSUPPORTED for what the delegate cannot
 *  edit in place yet (see docs/plugins.md). */
PRD_API PrdStatus prdSetAttributeNumbers(PrdDelegate* delegate, const char* primPath,
                                         const char* attribute, const double* values,
                                         size_t count);
/** Replaces the whole local transform of prim `primPath` with `matrix` (16 values in USD
 *  order as written in .usda, translation in elements 12..14; xformOpOrder is ignored after
 *  this) and marks every mesh, camera and light at or below it Transform-dirty: an instance
 *  moves without any mesh rebuild. */
PRD_API PrdStatus prdSetLocalTransform(PrdDelegate* delegate, const char* primPath,
                                       const double matrix[16]);
/** Same for token and string attributes (e.g. a light's texture file, a shading-model token). */
PRD_API PrdStatus prdSetAttributeString(PrdDelegate* delegate, const char* primPath,
                                        const char* attribute, const char* value);

/** Scene edits (PRD_ABI_MINOR 1; PRD_ERROR_UNSUPPORTED from an older plugin). Each marks only
 *  the dirty bits it implies (docs/usda.md, "Host edits"); on failure nothing changed and
 *  prdLastError names the prim path and what was expected. */
/** Defines a prim ("Mesh", "Sphere", "Cube", "Xform", "Material", "Shader", "Camera",
 *  "SphereLight", "PointInstancer", ...) whose parent exists; author its attributes next. */
PRD_API PrdStatus prdAddPrim(PrdDelegate* delegate, const char* primPath, const char* typeName);
/** Removes a prim and its subtree. Prims bound to a removed material use the default one. */
PRD_API PrdStatus prdRemovePrim(PrdDelegate* delegate, const char* primPath);
/** Binds a Material (material:binding) to a prim or GeomSubset; NULL or "" unbinds. */
PRD_API PrdStatus prdBindMaterial(PrdDelegate* delegate, const char* primPath,
                                  const char* materialPath);
/** Sets the targets of a relationship (e.g. a PointInstancer's "prototypes"). */
PRD_API PrdStatus prdSetRelationship(PrdDelegate* delegate, const char* primPath,
                                     const char* name, const char* const* targets, size_t count);
/** Connects a shading input/output to a source ("/Mat/Shader.outputs:surface"); "" disconnects. */
PRD_API PrdStatus prdConnectAttribute(PrdDelegate* delegate, const char* primPath,
                                      const char* attribute, const char* source);
/** Like prdSetAttributeNumbers, creating the attribute with `typeName` ("float3[]",
 *  "texCoord2f[]", "int") when it does not exist (an existing one must have that type). */
PRD_API PrdStatus prdSetAttributeTyped(PrdDelegate* delegate, const char* primPath,
                                       const char* attribute, const char* typeName,
                                       const double* values, size_t count);

/* ---- Host-supplied scenes ------------------------------------------------------------ */

/** Builds a scene from host data (a DCC's meshes, materials, lights, cameras) as USDA text
 *  that prdOpenStageFromBuilder opens like any stage, so edits, AOVs and warnings work the
 *  same. Builder calls report failures through prdLastError(NULL). Prim paths are absolute
 *  ("/World/Mesh"); missing ancestors become Xforms. */
typedef struct PrdSceneBuilder PrdSceneBuilder;

PRD_API PrdStatus prdSceneBuilderCreate(PrdSceneBuilder** out);
PRD_API void prdSceneBuilderDestroy(PrdSceneBuilder* builder);
/** Stage metadata: up axis "Y" or "Z" (default "Y") and meters per unit (default 0.01). */
PRD_API PrdStatus prdSceneSetStageMetadata(PrdSceneBuilder* b, const char* upAxis,
                                           double metersPerUnit);
/** Defines a prim of a USD type ("Xform", "Camera", "DistantLight", "SphereLight", ...). */
PRD_API PrdStatus prdSceneAddPrim(PrdSceneBuilder* b, const char* path, const char* typeName);
/** A polygon mesh: `pointCount` points (3 floats each), `faceCount` faces with their vertex
 *  counts, `indexCount` vertex indices. Subdivision is off ("none"). */
PRD_API PrdStatus prdSceneAddMesh(PrdSceneBuilder* b, const char* path, const float* points,
                                  size_t pointCount, const int* faceVertexCounts,
                                  size_t faceCount, const int* faceVertexIndices,
                                  size_t indexCount);
/** Authors attribute `name` of USD type `typeName` ("float", "color3f", "double3",
 *  "matrix4d", "normal3f[]", "texCoord2f[]", ...) from `count` numbers (an array's tuples
 *  flattened). `interpolation` (may be NULL) is authored as metadata for primvars. */
PRD_API PrdStatus prdSceneSetAttribute(PrdSceneBuilder* b, const char* path,
                                       const char* typeName, const char* name,
                                       const double* values, size_t count,
                                       const char* interpolation);
/** Authors a token, string or asset attribute (typeName "token", "string" or "asset"). */
PRD_API PrdStatus prdSceneSetAttributeString(PrdSceneBuilder* b, const char* path,
                                             const char* typeName, const char* name,
                                             const char* value);
/** The prim's local transform (16 values, USD order, translation in 12..14). */
PRD_API PrdStatus prdSceneSetTransform(PrdSceneBuilder* b, const char* path,
                                       const double matrix[16]);
/** A UsdPreviewSurface material at `path` (its shader is `path`/Surface). */
PRD_API PrdStatus prdSceneAddMaterial(PrdSceneBuilder* b, const char* path);
/** A surface input: 1 number -> float, 3 -> color3f ("normal" -> normal3f); integers for
 *  "useSpecularWorkflow". */
PRD_API PrdStatus prdSceneSetMaterialInput(PrdSceneBuilder* b, const char* materialPath,
                                           const char* input, const double* values,
                                           size_t count);
/** Connects a surface input to an image (UsdUVTexture reading primvar "st"); `channel` is
 *  "rgb" for colors or "r"/"g"/"b"/"a" for scalars. */
PRD_API PrdStatus prdSceneSetMaterialTexture(PrdSceneBuilder* b, const char* materialPath,
                                             const char* input, const char* file,
                                             const char* channel);
/** Binds a material to a prim (material:binding). */
PRD_API PrdStatus prdSceneBindMaterial(PrdSceneBuilder* b, const char* primPath,
                                       const char* materialPath);
/** The USDA text built so far; valid until the next builder call. */
PRD_API PrdStatus prdSceneToUsda(PrdSceneBuilder* b, const char** text);
/** Opens the built scene on a delegate (like prdOpenStageString). */
PRD_API PrdStatus prdOpenStageFromBuilder(PrdDelegate* delegate, PrdSceneBuilder* b);

/* ---- Settings ------------------------------------------------------------------------ */

PRD_API PrdStatus prdSetSettingInt(PrdDelegate* delegate, const char* key, int64_t value);
PRD_API PrdStatus prdSetSettingFloat(PrdDelegate* delegate, const char* key, double value);
PRD_API PrdStatus prdSetSettingString(PrdDelegate* delegate, const char* key, const char* value);
/** Number of render settings the delegate describes. */
PRD_API PrdStatus prdSettingCount(PrdDelegate* delegate, int* count);
/** Descriptor `index`; strings valid until the delegate is destroyed. */
PRD_API PrdStatus prdSettingDescriptor(PrdDelegate* delegate, int index,
                                       PrdSettingDescriptor* out);
/** The current value as text ("64", "0.5", "disney"); valid until the next call. */
PRD_API PrdStatus prdGetSetting(PrdDelegate* delegate, const char* key, const char** valueText);

/* ---- Camera, resolution, AOVs -------------------------------------------------------- */

/** The camera prim to render through; NULL or "" = the stage's first camera, else a camera
 *  framing the scene. Checked against the stage when one is open (or at the next open). */
PRD_API PrdStatus prdSetCamera(PrdDelegate* delegate, const char* primPath);
/** The camera actually used (after a stage is open); valid until the next call. */
PRD_API PrdStatus prdGetCamera(PrdDelegate* delegate, const char** primPath);
/** Image size in pixels, 1..32768 each (default 640x360). Bound buffers are reallocated. */
PRD_API PrdStatus prdSetResolution(PrdDelegate* delegate, int width, int height);
/** How the image frames the camera (PRD_ABI_MINOR 2; PRD_ERROR_UNSUPPORTED from an older
 *  plugin), as UsdRenderSettingsBase's attributes: conformPolicy "expandAperture" (the
 *  fallback), "cropAperture", "adjustApertureWidth", "adjustApertureHeight" or
 *  "adjustPixelAspectRatio"; pixelAspectRatio 1e-4..1e4 (pixel width / height); dataWindowNDC
 *  (xmin, ymin, xmax, ymax) within the unit square, (0, 0) the bottom left, NULL = all of it:
 *  only pixels whose centres lie in it are rendered (a crop; the rest stay at their clear
 *  value). conformPolicy NULL returns to the stage's own RenderSettings framing. Kept across
 *  stages, like the resolution. */
PRD_API PrdStatus prdSetFraming(PrdDelegate* delegate, const char* conformPolicy, double pixelAspectRatio,
                                const double dataWindowNDC[4]);

/** Texture files edited on disk are read again from the next pass (PRD_ABI_MINOR 2;
 *  PRD_ERROR_UNSUPPORTED from an older plugin): with onlyChanged, those whose modification
 *  time or size changed since they were read (material textures and light images); else
 *  all of them. *reloaded (may be NULL) is set to 1 when anything is re-read (the image then
 *  restarts), else 0. Needs an open stage. */
PRD_API PrdStatus prdReloadTextures(PrdDelegate* delegate, int onlyChanged, int* reloaded);

/** AOVs this renderer can bind ("color", "depth", "primId", ...). */
PRD_API PrdStatus prdAovCount(PrdDelegate* delegate, int* count);
/** AOV `index`: name, format, channels; strings valid until the delegate is destroyed. */
PRD_API PrdStatus prdAovInfo(PrdDelegate* delegate, int index, PrdAovInfo* out);
/** Looks an AOV up by name (PRD_ERROR_NOT_FOUND if the renderer has no such AOV). */
PRD_API PrdStatus prdAovDescribe(PrdDelegate* delegate, const char* name, PrdAovInfo* out);
/** Binds (allocates a render buffer for) an AOV; binding twice is a no-op. */
PRD_API PrdStatus prdBindAov(PrdDelegate* delegate, const char* name);
PRD_API PrdStatus prdUnbindAov(PrdDelegate* delegate, const char* name);

/* ---- Rendering ----------------------------------------------------------------------- */

/** Syncs pending edits and runs one progressive pass (blocking, parallel inside). The first
 *  pass after a change is cheap; *converged (may be NULL) is set to 1 once the target sample
 *  count is reached, after which passes return at once. */
PRD_API PrdStatus prdRenderPass(PrdDelegate* delegate, int* converged);
/** Progress since the last restart: converged flag and samples per pixel done / targeted. */
PRD_API PrdStatus prdProgress(PrdDelegate* delegate, int* converged, int* completedSamples,
                              int* targetSamples);
/** The resolved pixels of a bound AOV (top row first, `channels` values per pixel, row
 *  stride width*channels). Valid until the next prdRenderPass, prdSetResolution,
 *  prdOpenStage*, prdUnbindAov or prdDestroyDelegate on this delegate. */
PRD_API PrdStatus prdMapAov(PrdDelegate* delegate, const char* name, PrdBufferView* out);

/** Render statistics (rays, samples, BVH builds, seconds, ...) as key/value pairs, sorted by
 *  key; the snapshot is taken by prdStatCount and read with prdStat. */
PRD_API PrdStatus prdStatCount(PrdDelegate* delegate, int* count);
PRD_API PrdStatus prdStat(PrdDelegate* delegate, int index, const char** key, double* value);

/** Warnings about the scene (unsupported prims, bad values) gathered since the last call, one
 *  per line; "" if none. Valid until the next call. */
PRD_API PrdStatus prdTakeWarnings(PrdDelegate* delegate, const char** text);

#ifdef __cplusplus
}
#endif

#endif /* PRINCIPLED_C_H */
