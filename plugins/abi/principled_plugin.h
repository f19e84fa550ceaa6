/* SPDX-License-Identifier: Apache-2.0 */
/* principled_plugin.h: what a render-delegate plugin library exports. One C entry point,
 * PRD_PLUGIN_ENTRY_POINT, returns a table of C functions over an opaque session. The host
 * library (principled_c.h) wraps the table; hosts never call it directly unless they want to.
 * The table starts with its ABI version and size so a host checks compatibility before it
 * calls anything else. */
#ifndef PRINCIPLED_PLUGIN_H
#define PRINCIPLED_PLUGIN_H

#include <stddef.h>

#include "principled_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The exported symbol: `const PrdRendererApi* principledRendererPlugin(void);` */
#define PRD_PLUGIN_ENTRY_POINT "principledRendererPlugin"

/** One delegate instance inside a plugin (opaque to the host). */
typedef struct PrdSession PrdSession;

/** The plugin table. Every function except create reports failures through lastError(s);
 *  create reports through *error (a string owned by the plugin, valid until the next create
 *  on this thread). No function throws or aborts. Appended to only (PRD_ABI_MINOR). */
typedef struct PrdRendererApi {
    uint32_t abiVersion; /**< PRD_ABI_VERSION the plugin was built with */
    uint32_t structSize; /**< sizeof(PrdRendererApi) in the plugin */

    PrdStatus (*create)(const char* typeName, PrdSession** out, const char** error);
    void (*destroy)(PrdSession* s);
    const char* (*lastError)(const PrdSession* s);

    PrdStatus (*openStageFile)(PrdSession* s, const char* path);
    PrdStatus (*openStageString)(PrdSession* s, const char* text, const char* displayName);
    PrdStatus (*setAttributeNumbers)(PrdSession* s, const char* primPath, const char* attribute,
                                     const double* values, size_t count);
    PrdStatus (*setAttributeString)(PrdSession* s, const char* primPath, const char* attribute,
                                    const char* value);

    PrdStatus (*setLocalTransform)(PrdSession* s, const char* primPath, const double matrix[16]);

    PrdStatus (*setSettingInt)(PrdSession* s, const char* key, int64_t value);
    PrdStatus (*setSettingFloat)(PrdSession* s, const char* key, double value);
    PrdStatus (*setSettingString)(PrdSession* s, const char* key, const char* value);
    PrdStatus (*settingCount)(PrdSession* s, int* count);
    PrdStatus (*settingDescriptor)(PrdSession* s, int index, PrdSettingDescriptor* out);
    PrdStatus (*getSetting)(PrdSession* s, const char* key, const char** valueText);

    PrdStatus (*setCamera)(PrdSession* s, const char* primPath);
    PrdStatus (*getCamera)(PrdSession* s, const char** primPath);
    PrdStatus (*setResolution)(PrdSession* s, int width, int height);

    PrdStatus (*aovCount)(PrdSession* s, int* count);
    PrdStatus (*aovInfo)(PrdSession* s, int index, PrdAovInfo* out);
    PrdStatus (*aovDescribe)(PrdSession* s, const char* name, PrdAovInfo* out);
    PrdStatus (*bindAov)(PrdSession* s, const char* name);
    PrdStatus (*unbindAov)(PrdSession* s, const char* name);

    PrdStatus (*renderPass)(PrdSession* s, int* converged);
    PrdStatus (*progress)(PrdSession* s, int* converged, int* completedSamples,
                          int* targetSamples);
    PrdStatus (*mapAov)(PrdSession* s, const char* name, PrdBufferView* out);

    PrdStatus (*statCount)(PrdSession* s, int* count);
    PrdStatus (*stat)(PrdSession* s, int index, const char** key, double* value);
    PrdStatus (*takeWarnings)(PrdSession* s, const char** text);

    /* PRD_ABI_MINOR 1: scene edits beyond attribute values (a host checks structSize). */
    PrdStatus (*addPrim)(PrdSession* s, const char* primPath, const char* typeName);
    PrdStatus (*removePrim)(PrdSession* s, const char* primPath);
    PrdStatus (*bindMaterial)(PrdSession* s, const char* primPath, const char* materialPath);
    PrdStatus (*setRelationship)(PrdSession* s, const char* primPath, const char* name,
                                 const char* const* targets, size_t count);
    PrdStatus (*connectAttribute)(PrdSession* s, const char* primPath, const char* attribute,
                                  const char* source);
    PrdStatus (*setAttributeTyped)(PrdSession* s, const char* primPath, const char* attribute,
                                   const char* typeName, const double* values, size_t count);

    /* PRD_ABI_MINOR 2: the image's framing (UsdRender conform policy, pixel aspect, data window)
     * and texture reloading. */
    PrdStatus (*setFraming)(PrdSession* s, const char* conformPolicy, double pixelAspectRatio,
                            const double dataWindowNDC[4]);
    PrdStatus (*reloadTextures)(PrdSession* s, int onlyChanged, int* reloaded);
} PrdRendererApi;

/** Size of a PRD_ABI_MINOR 0 table (up to takeWarnings): the smallest a host accepts. */
#define PRD_RENDERER_API_SIZE_V1_0 (offsetof(PrdRendererApi, addPrim))

/** Signature of the entry point. */
typedef const PrdRendererApi* (*PrdRendererPluginFn)(void);

#ifdef __cplusplus
}
#endif

#endif /* PRINCIPLED_PLUGIN_H */
