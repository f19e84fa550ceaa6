// SPDX-License-Identifier: Apache-2.0
// The Embree delegate's plugin table. The plugin library returns it from its entry point; a
// host that links the delegate statically passes it to prdCreateDelegateFromApi() instead.
#pragma once

#include "plugins/abi/principled_plugin.h"

#ifdef __cplusplus
extern "C" {
#endif

/// The renderer type this table creates (plugInfo.json "Types" key).
#define PRD_EMBREE_TYPE_NAME "PrincipledEmbreeRenderer"

const PrdRendererApi* prdEmbreeRendererApi(void);

#ifdef __cplusplus
}
#endif
