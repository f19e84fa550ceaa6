// SPDX-License-Identifier: Apache-2.0
// The host side of the C ABI (principled_c.h): finds renderers through the plugin registry and
// forwards every call to the plugin's table, keeping the last error per handle.
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "plugins/abi/principled_c.h"
#include "plugins/registry/pluginRegistry.h"

struct PrdDelegate {
    const PrdRendererApi* api = nullptr;
    PrdSession* session = nullptr;
    std::string error;
};

namespace {

using principled::plugins::PluginRegistry;

thread_local std::string tlsError;

PrdStatus failNoHandle(PrdStatus status, std::string message) {
    tlsError = std::move(message);
    return status;
}

/// Runs one plugin call: checks the handle, clears or records the error.
template <typename F>
PrdStatus forward(PrdDelegate* d, const char* call, F&& f) {
    if (!d) return failNoHandle(PRD_ERROR_NULL_HANDLE, std::string(call) + ": delegate is NULL");
    PrdStatus s;
    try {
        s = f(d->api, d->session);
    } catch (const std::exception& e) {  // a plugin must not throw; never let it cross anyway
        d->error = std::string(call) + ": " + e.what();
        return PRD_ERROR_INTERNAL;
    } catch (...) {
        d->error = std::string(call) + ": unknown exception";
        return PRD_ERROR_INTERNAL;
    }
    if (s == PRD_OK) {
        d->error.clear();
    } else {
        const char* m = d->api->lastError(d->session);
        d->error = std::string(call) + ": " + (m && *m ? m : prdStatusName(s));
    }
    return s;
}

/// forward() for calls a PRD_ABI_MINOR 0 plugin table does not have.
template <typename F>
PrdStatus forwardNew(PrdDelegate* d, const char* call, bool has, F&& f) {
    if (d && !has) {
        d->error = std::string(call) + ": the renderer plugin is too old for this call";
        return PRD_ERROR_UNSUPPORTED;
    }
    return forward(d, call, std::forward<F>(f));
}


std::string registryDiagnostics;

}  // namespace

/// Lets the scene builder (sceneBuilder.cpp) report through prdLastError(NULL).
void prdSetThreadError(const std::string& message) {
    tlsError = message;
}

extern "C" {

uint32_t prdAbiVersion(void) {
    return PRD_ABI_VERSION;
}

const char* prdStatusName(PrdStatus status) {
    switch (status) {
        case PRD_OK:
            return "PRD_OK";
        case PRD_ERROR_NULL_HANDLE:
            return "PRD_ERROR_NULL_HANDLE";
        case PRD_ERROR_INVALID_ARGUMENT:
            return "PRD_ERROR_INVALID_ARGUMENT";
        case PRD_ERROR_NOT_FOUND:
            return "PRD_ERROR_NOT_FOUND";
        case PRD_ERROR_IO:
            return "PRD_ERROR_IO";
        case PRD_ERROR_NO_STAGE:
            return "PRD_ERROR_NO_STAGE";
        case PRD_ERROR_NOT_BOUND:
            return "PRD_ERROR_NOT_BOUND";
        case PRD_ERROR_UNSUPPORTED:
            return "PRD_ERROR_UNSUPPORTED";
        case PRD_ERROR_PLUGIN:
            return "PRD_ERROR_PLUGIN";
        case PRD_ERROR_INTERNAL:
            return "PRD_ERROR_INTERNAL";
    }
    return "PRD_ERROR_UNKNOWN_STATUS";
}

const char* prdLastError(const PrdDelegate* d) {
    return d ? d->error.c_str() : tlsError.c_str();
}

int prdRendererCount(void) {
    try {
        return static_cast<int>(PluginRegistry::instance().renderers().size());
    } catch (...) {
        return 0;
    }
}

PrdStatus prdRendererInfo(int index, PrdRendererInfo* info) {
    if (!info) return failNoHandle(PRD_ERROR_INVALID_ARGUMENT, "prdRendererInfo: info is NULL");
    try {
        // Entries are copied into process-lifetime storage so the strings stay valid.
        static std::vector<std::unique_ptr<principled::plugins::RendererEntry>> keep;
        static std::mutex keepMutex;
        auto list = PluginRegistry::instance().renderers();
        if (index < 0 || index >= static_cast<int>(list.size()))
            return failNoHandle(PRD_ERROR_NOT_FOUND, "prdRendererInfo: index " +
                                                         std::to_string(index) + " out of range (" +
                                                         std::to_string(list.size()) +
                                                         " renderers)");
        std::lock_guard lock(keepMutex);
        const principled::plugins::RendererEntry* e = nullptr;
        for (const auto& k : keep)
            if (k->typeName == list[index].typeName && k->libraryPath == list[index].libraryPath &&
                k->priority == list[index].priority && k->displayName == list[index].displayName)
                e = k.get();
        if (!e) {
            keep.push_back(std::make_unique<principled::plugins::RendererEntry>(list[index]));
            e = keep.back().get();
        }
        info->typeName = e->typeName.c_str();
        info->displayName = e->displayName.c_str();
        info->pluginName = e->pluginName.c_str();
        info->libraryPath = e->libraryPath.c_str();
        info->priority = e->priority;
        info->loaded = PluginRegistry::instance().isLoaded(e->typeName) ? 1 : 0;
        return PRD_OK;
    } catch (const std::exception& ex) {
        return failNoHandle(PRD_ERROR_INTERNAL, std::string("prdRendererInfo: ") + ex.what());
    }
}

const char* prdRegistryDiagnostics(void) {
    static std::mutex m;
    std::lock_guard lock(m);
    try {
        registryDiagnostics.clear();
        for (const auto& d : PluginRegistry::instance().diagnostics())
            registryDiagnostics += d + "\n";
    } catch (...) {
    }
    return registryDiagnostics.c_str();
}

PrdStatus prdCreateDelegateFromApi(const PrdRendererApi* api, const char* typeName,
                                   PrdDelegate** out) {
    if (!out) return failNoHandle(PRD_ERROR_INVALID_ARGUMENT, "prdCreateDelegate: out is NULL");
    *out = nullptr;
    if (!api) return failNoHandle(PRD_ERROR_INVALID_ARGUMENT, "prdCreateDelegate: api is NULL");
    if (api->abiVersion != PRD_ABI_VERSION || api->structSize < PRD_RENDERER_API_SIZE_V1_0)
        return failNoHandle(PRD_ERROR_PLUGIN,
                            "prdCreateDelegate: plugin table has ABI version " +
                                std::to_string(api->abiVersion) + " and size " +
                                std::to_string(api->structSize) + "; this host needs version " +
                                std::to_string(PRD_ABI_VERSION) +
                                " and size >= " + std::to_string(PRD_RENDERER_API_SIZE_V1_0));
    try {
        PrdSession* session = nullptr;
        const char* error = nullptr;
        PrdStatus s = api->create(typeName ? typeName : "", &session, &error);
        if (s != PRD_OK || !session)
            return failNoHandle(
                s == PRD_OK ? PRD_ERROR_INTERNAL : s,
                std::string("prdCreateDelegate: ") +
                    (error && *error ? error : "the plugin could not create a delegate"));
        auto* d = new PrdDelegate;
        d->api = api;
        d->session = session;
        *out = d;
        tlsError.clear();
        return PRD_OK;
    } catch (const std::exception& e) {
        return failNoHandle(PRD_ERROR_INTERNAL, std::string("prdCreateDelegate: ") + e.what());
    }
}

PrdStatus prdCreateDelegate(const char* name, PrdDelegate** out) {
    if (!out) return failNoHandle(PRD_ERROR_INVALID_ARGUMENT, "prdCreateDelegate: out is NULL");
    *out = nullptr;
    try {
        std::string error;
        auto& registry = PluginRegistry::instance();
        std::string wanted = name ? name : "";
        auto entry = registry.find(wanted);
        if (!entry)
            return failNoHandle(PRD_ERROR_NOT_FOUND,
                                "prdCreateDelegate: " + registry.notFoundMessage(wanted));
        const PrdRendererApi* api = registry.load(entry->typeName, &error);
        if (!api) return failNoHandle(PRD_ERROR_PLUGIN, "prdCreateDelegate: " + error);
        return prdCreateDelegateFromApi(api, entry->typeName.c_str(), out);
    } catch (const std::exception& e) {
        return failNoHandle(PRD_ERROR_INTERNAL, std::string("prdCreateDelegate: ") + e.what());
    }
}

void prdDestroyDelegate(PrdDelegate* d) {
    if (!d) return;
    try {
        d->api->destroy(d->session);
    } catch (...) {
    }
    delete d;
}

PrdStatus prdOpenStageFile(PrdDelegate* d, const char* path) {
    return forward(d, "prdOpenStageFile", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->openStageFile(s, path);
    });
}
PrdStatus prdOpenStageString(PrdDelegate* d, const char* text, const char* displayName) {
    return forward(d, "prdOpenStageString", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->openStageString(s, text, displayName);
    });
}
PrdStatus prdSetAttributeNumbers(PrdDelegate* d, const char* primPath, const char* attribute,
                                 const double* values, size_t count) {
    return forward(d, "prdSetAttributeNumbers", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setAttributeNumbers(s, primPath, attribute, values, count);
    });
}
PrdStatus prdSetAttributeString(PrdDelegate* d, const char* primPath, const char* attribute,
                                const char* value) {
    return forward(d, "prdSetAttributeString", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setAttributeString(s, primPath, attribute, value);
    });
}
PrdStatus prdSetLocalTransform(PrdDelegate* d, const char* primPath, const double matrix[16]) {
    return forward(d, "prdSetLocalTransform", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setLocalTransform(s, primPath, matrix);
    });
}
// Calls added in PRD_ABI_MINOR 1: an older plugin's table ends before them.
#define PRD_HAS(api, field) \
    ((api)->structSize >= offsetof(PrdRendererApi, field) + sizeof((api)->field) && (api)->field)

PrdStatus prdAddPrim(PrdDelegate* d, const char* primPath, const char* typeName) {
    return forwardNew(d, "prdAddPrim", d && PRD_HAS(d->api, addPrim),
                      [&](const PrdRendererApi* a, PrdSession* s) { return a->addPrim(s, primPath, typeName); });
}
PrdStatus prdRemovePrim(PrdDelegate* d, const char* primPath) {
    return forwardNew(d, "prdRemovePrim", d && PRD_HAS(d->api, removePrim),
                      [&](const PrdRendererApi* a, PrdSession* s) { return a->removePrim(s, primPath); });
}
PrdStatus prdBindMaterial(PrdDelegate* d, const char* primPath, const char* materialPath) {
    return forwardNew(d, "prdBindMaterial", d && PRD_HAS(d->api, bindMaterial),
                      [&](const PrdRendererApi* a, PrdSession* s) {
                          return a->bindMaterial(s, primPath, materialPath);
                      });
}
PrdStatus prdSetRelationship(PrdDelegate* d, const char* primPath, const char* name,
                             const char* const* targets, size_t count) {
    return forwardNew(d, "prdSetRelationship", d && PRD_HAS(d->api, setRelationship),
                      [&](const PrdRendererApi* a, PrdSession* s) {
                          return a->setRelationship(s, primPath, name, targets, count);
                      });
}
PrdStatus prdConnectAttribute(PrdDelegate* d, const char* primPath, const char* attribute,
                              const char* source) {
    return forwardNew(d, "prdConnectAttribute", d && PRD_HAS(d->api, connectAttribute),
                      [&](const PrdRendererApi* a, PrdSession* s) {
                          return a->connectAttribute(s, primPath, attribute, source);
                      });
}
PrdStatus prdSetAttributeTyped(PrdDelegate* d, const char* primPath, const char* attribute,
                               const char* typeName, const double* values, size_t count) {
    return forwardNew(d, "prdSetAttributeTyped", d && PRD_HAS(d->api, setAttributeTyped),
                      [&](const PrdRendererApi* a, PrdSession* s) {
                          return a->setAttributeTyped(s, primPath, attribute, typeName, values, count);
                      });
}

PrdStatus prdSetSettingInt(PrdDelegate* d, const char* key, int64_t value) {
    return forward(d, "prdSetSettingInt", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setSettingInt(s, key, value);
    });
}
PrdStatus prdSetSettingFloat(PrdDelegate* d, const char* key, double value) {
    return forward(d, "prdSetSettingFloat", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setSettingFloat(s, key, value);
    });
}
PrdStatus prdSetSettingString(PrdDelegate* d, const char* key, const char* value) {
    return forward(d, "prdSetSettingString", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setSettingString(s, key, value);
    });
}
PrdStatus prdSettingCount(PrdDelegate* d, int* count) {
    return forward(d, "prdSettingCount", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->settingCount(s, count);
    });
}
PrdStatus prdSettingDescriptor(PrdDelegate* d, int index, PrdSettingDescriptor* out) {
    return forward(d, "prdSettingDescriptor", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->settingDescriptor(s, index, out);
    });
}
PrdStatus prdGetSetting(PrdDelegate* d, const char* key, const char** valueText) {
    return forward(d, "prdGetSetting", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->getSetting(s, key, valueText);
    });
}
PrdStatus prdSetCamera(PrdDelegate* d, const char* primPath) {
    return forward(d, "prdSetCamera", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setCamera(s, primPath);
    });
}
PrdStatus prdGetCamera(PrdDelegate* d, const char** primPath) {
    return forward(d, "prdGetCamera", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->getCamera(s, primPath);
    });
}
PrdStatus prdSetResolution(PrdDelegate* d, int width, int height) {
    return forward(d, "prdSetResolution", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->setResolution(s, width, height);
    });
}
PrdStatus prdSetFraming(PrdDelegate* d, const char* conformPolicy, double pixelAspectRatio,
                        const double dataWindowNDC[4]) {
    return forwardNew(d, "prdSetFraming", d && PRD_HAS(d->api, setFraming),
                      [&](const PrdRendererApi* a, PrdSession* s) {
                          return a->setFraming(s, conformPolicy, pixelAspectRatio, dataWindowNDC);
                      });
}
PrdStatus prdReloadTextures(PrdDelegate* d, int onlyChanged, int* reloaded) {
    return forwardNew(d, "prdReloadTextures", d && PRD_HAS(d->api, reloadTextures),
                      [&](const PrdRendererApi* a, PrdSession* s) { return a->reloadTextures(s, onlyChanged, reloaded); });
}
PrdStatus prdAovCount(PrdDelegate* d, int* count) {
    return forward(d, "prdAovCount",
                   [&](const PrdRendererApi* a, PrdSession* s) { return a->aovCount(s, count); });
}
PrdStatus prdAovInfo(PrdDelegate* d, int index, PrdAovInfo* out) {
    return forward(d, "prdAovInfo", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->aovInfo(s, index, out);
    });
}
PrdStatus prdAovDescribe(PrdDelegate* d, const char* name, PrdAovInfo* out) {
    return forward(d, "prdAovDescribe", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->aovDescribe(s, name, out);
    });
}
PrdStatus prdBindAov(PrdDelegate* d, const char* name) {
    return forward(d, "prdBindAov",
                   [&](const PrdRendererApi* a, PrdSession* s) { return a->bindAov(s, name); });
}
PrdStatus prdUnbindAov(PrdDelegate* d, const char* name) {
    return forward(d, "prdUnbindAov",
                   [&](const PrdRendererApi* a, PrdSession* s) { return a->unbindAov(s, name); });
}
PrdStatus prdRenderPass(PrdDelegate* d, int* converged) {
    return forward(d, "prdRenderPass", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->renderPass(s, converged);
    });
}
PrdStatus prdProgress(PrdDelegate* d, int* converged, int* completedSamples, int* targetSamples) {
    return forward(d, "prdProgress", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->progress(s, converged, completedSamples, targetSamples);
    });
}
PrdStatus prdMapAov(PrdDelegate* d, const char* name, PrdBufferView* out) {
    return forward(d, "prdMapAov",
                   [&](const PrdRendererApi* a, PrdSession* s) { return a->mapAov(s, name, out); });
}
PrdStatus prdStatCount(PrdDelegate* d, int* count) {
    return forward(d, "prdStatCount",
                   [&](const PrdRendererApi* a, PrdSession* s) { return a->statCount(s, count); });
}
PrdStatus prdStat(PrdDelegate* d, int index, const char** key, double* value) {
    return forward(d, "prdStat", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->stat(s, index, key, value);
    });
}
PrdStatus prdTakeWarnings(PrdDelegate* d, const char** text) {
    return forward(d, "prdTakeWarnings", [&](const PrdRendererApi* a, PrdSession* s) {
        return a->takeWarnings(s, text);
    });
}

}  // extern "C"
