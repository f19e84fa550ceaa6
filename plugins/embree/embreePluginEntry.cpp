// SPDX-License-Identifier: Apache-2.0
// The one symbol the Embree plugin library exports (everything else is hidden).
#include "plugins/embree/embreePlugin.h"

extern "C" __attribute__((visibility("default"))) const PrdRendererApi* principledRendererPlugin(
    void) {
    return prdEmbreeRendererApi();
}
