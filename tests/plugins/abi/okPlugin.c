/* SPDX-License-Identifier: Apache-2.0 */
/* A test plugin with a valid table whose create always fails with a message. */
#include "plugins/abi/principled_plugin.h"

static PrdStatus create(const char* typeName, PrdSession** out, const char** error) {
    (void)typeName;
    *out = 0;
    *error = "fake plugin: create always fails";
    return PRD_ERROR_UNSUPPORTED;
}

static PrdRendererApi api;

__attribute__((visibility("default"))) const PrdRendererApi* principledRendererPlugin(void) {
    api.abiVersion = PRD_ABI_VERSION;
    api.structSize = sizeof(PrdRendererApi);
    api.create = create;
    return &api;
}
