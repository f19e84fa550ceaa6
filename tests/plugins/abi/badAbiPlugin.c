/* SPDX-License-Identifier: Apache-2.0 */
/* A test plugin built against a future ABI: the host must refuse it before calling anything. */
#include "plugins/abi/principled_plugin.h"

static PrdRendererApi api;

__attribute__((visibility("default"))) const PrdRendererApi* principledRendererPlugin(void) {
    api.abiVersion = 999;
    api.structSize = sizeof(PrdRendererApi);
    return &api;
}
