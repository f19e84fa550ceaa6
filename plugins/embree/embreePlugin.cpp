// SPDX-License-Identifier: Apache-2.0
// The C table over EmbreeSession: argument checks, and every exception turned into a status
// plus a message kept on the session. Nothing throws past this file.
#include "plugins/embree/embreePlugin.h"

#include <new>
#include <string>
#include <vector>

#include "plugins/embree/embreeSession.h"
#include "scene_adapter/stageEditor.h"

using principled::adapter::EditValue;
using principled::plugins::EmbreeSession;
using principled::plugins::SessionError;
using principled::plugins::SettingInput;

struct PrdSession {
    EmbreeSession impl;
    std::string error;
};

namespace {

thread_local std::string createError;

template <typename F>
PrdStatus guard(PrdSession* s, F&& f) {
    if (!s) return PRD_ERROR_NULL_HANDLE;
    try {
        f(s->impl);
        s->error.clear();
        return PRD_OK;
    } catch (const SessionError& e) {
        s->error = e.what();
        return e.status;
    } catch (const std::bad_alloc&) {
        s->error = "out of memory";
        return PRD_ERROR_INTERNAL;
    } catch (const std::exception& e) {
        s->error = std::string("internal error: ") + e.what();
        return PRD_ERROR_INTERNAL;
    } catch (...) {
        s->error = "internal error: unknown exception";
        return PRD_ERROR_INTERNAL;
    }
}

template <typename T>
T* need(T* p, const char* what) {
    if (!p) throw SessionError(PRD_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL");
    return p;
}

PrdStatus create(const char* typeName, PrdSession** out, const char** error) {
    createError.clear();
    if (error) *error = createError.c_str();
    if (!out) {
        createError = "out is NULL";
        return PRD_ERROR_INVALID_ARGUMENT;
    }
    *out = nullptr;
    std::string t = typeName ? typeName : "";
    if (!t.empty() && t != PRD_EMBREE_TYPE_NAME && t != "Embree") {
        createError = "this plugin provides '" PRD_EMBREE_TYPE_NAME "', not '" + t + "'";
        if (error) *error = createError.c_str();
        return PRD_ERROR_NOT_FOUND;
    }
    try {
        *out = new PrdSession;
        return PRD_OK;
    } catch (const std::exception& e) {
        createError = std::string("cannot create the Embree delegate: ") + e.what();
        if (error) *error = createError.c_str();
        return PRD_ERROR_INTERNAL;
    }
}

void destroy(PrdSession* s) {
    try {
        delete s;
    } catch (...) {
    }
}

const char* lastError(const PrdSession* s) {
    return s ? s->error.c_str() : "";
}

PrdStatus openStageFile(PrdSession* s, const char* path) {
    return guard(s, [&](EmbreeSession& e) { e.openFile(need(path, "path")); });
}
PrdStatus openStageString(PrdSession* s, const char* text, const char* name) {
    return guard(s,
                 [&](EmbreeSession& e) { e.openString(need(text, "usdaText"), name ? name : ""); });
}
PrdStatus setAttributeNumbers(PrdSession* s, const char* prim, const char* attr,
                              const double* values, size_t count) {
    return guard(s, [&](EmbreeSession& e) {
        EditValue v;
        if (count == 0) throw SessionError(PRD_ERROR_INVALID_ARGUMENT, "count is 0");
        need(values, "values");
        v.numbers.assign(values, values + count);
        e.setAttribute(need(prim, "primPath"), need(attr, "attribute"), v);
    });
}
PrdStatus setAttributeString(PrdSession* s, const char* prim, const char* attr, const char* value) {
    return guard(s, [&](EmbreeSession& e) {
        e.setAttribute(need(prim, "primPath"), need(attr, "attribute"),
                       EditValue::text(need(value, "value")));
    });
}
PrdStatus setLocalTransform(PrdSession* s, const char* prim, const double matrix[16]) {
    return guard(s, [&](EmbreeSession& e) {
        e.setLocalTransform(need(prim, "primPath"), need(matrix, "matrix"));
    });
}
PrdStatus addPrim(PrdSession* s, const char* prim, const char* type) {
    return guard(s, [&](EmbreeSession& e) { e.addPrim(need(prim, "primPath"), need(type, "typeName")); });
}
PrdStatus removePrim(PrdSession* s, const char* prim) {
    return guard(s, [&](EmbreeSession& e) { e.removePrim(need(prim, "primPath")); });
}
PrdStatus bindMaterial(PrdSession* s, const char* prim, const char* material) {
    return guard(s, [&](EmbreeSession& e) { e.bindMaterial(need(prim, "primPath"), material ? material : ""); });
}
PrdStatus setRelationship(PrdSession* s, const char* prim, const char* name,
                          const char* const* targets, size_t count) {
    return guard(s, [&](EmbreeSession& e) {
        if (count) need(targets, "targets");
        std::vector<std::string> t;
        for (size_t i = 0; i < count; ++i) t.emplace_back(need(targets[i], "a target"));
        e.setRelationship(need(prim, "primPath"), need(name, "name"), t);
    });
}
PrdStatus connectAttribute(PrdSession* s, const char* prim, const char* attr, const char* source) {
    return guard(s, [&](EmbreeSession& e) {
        e.connect(need(prim, "primPath"), need(attr, "attribute"), source ? source : "");
    });
}
PrdStatus setAttributeTyped(PrdSession* s, const char* prim, const char* attr, const char* type,
                            const double* values, size_t count) {
    return guard(s, [&](EmbreeSession& e) {
        if (count) need(values, "values");
        EditValue v;
        if (count) v.numbers.assign(values, values + count);
        e.setAttribute(need(prim, "primPath"), need(attr, "attribute"), v, need(type, "typeName"));
    });
}
PrdStatus setSettingInt(PrdSession* s, const char* key, int64_t value) {
    return guard(s, [&](EmbreeSession& e) {
        SettingInput in;
        in.type = PRD_TYPE_INT;
        in.i = value;
        e.setSetting(need(key, "key"), in);
    });
}
PrdStatus setSettingFloat(PrdSession* s, const char* key, double value) {
    return guard(s, [&](EmbreeSession& e) {
        SettingInput in;
        in.type = PRD_TYPE_FLOAT;
        in.f = value;
        e.setSetting(need(key, "key"), in);
    });
}
PrdStatus setSettingString(PrdSession* s, const char* key, const char* value) {
    return guard(s, [&](EmbreeSession& e) {
        SettingInput in;
        in.type = PRD_TYPE_STRING;
        in.s = need(value, "value");
        e.setSetting(need(key, "key"), in);
    });
}
PrdStatus settingCount(PrdSession* s, int* count) {
    return guard(s, [&](EmbreeSession& e) { *need(count, "count") = e.settingCount(); });
}
PrdStatus settingDescriptor(PrdSession* s, int index, PrdSettingDescriptor* out) {
    return guard(s, [&](EmbreeSession& e) { *need(out, "out") = e.settingDescriptor(index); });
}
PrdStatus getSetting(PrdSession* s, const char* key, const char** text) {
    return guard(
        s, [&](EmbreeSession& e) { *need(text, "valueText") = e.settingText(need(key, "key")); });
}
PrdStatus setCamera(PrdSession* s, const char* prim) {
    return guard(s, [&](EmbreeSession& e) { e.setCamera(prim ? prim : ""); });
}
PrdStatus getCamera(PrdSession* s, const char** prim) {
    return guard(s, [&](EmbreeSession& e) { *need(prim, "primPath") = e.camera().c_str(); });
}
PrdStatus setResolution(PrdSession* s, int width, int height) {
    return guard(s, [&](EmbreeSession& e) { e.setResolution(width, height); });
}
PrdStatus setFraming(PrdSession* s, const char* conformPolicy, double pixelAspectRatio, const double dataWindowNDC[4]) {
    return guard(s, [&](EmbreeSession& e) { e.setFraming(conformPolicy, pixelAspectRatio, dataWindowNDC); });
}
PrdStatus reloadTextures(PrdSession* s, int onlyChanged, int* reloaded) {
    return guard(s, [&](EmbreeSession& e) {
        const bool r = e.reloadTextures(onlyChanged != 0);
        if (reloaded) *reloaded = r ? 1 : 0;
    });
}
PrdStatus aovCount(PrdSession* s, int* count) {
    return guard(s, [&](EmbreeSession& e) { *need(count, "count") = e.aovCount(); });
}
PrdStatus aovInfo(PrdSession* s, int index, PrdAovInfo* out) {
    return guard(s, [&](EmbreeSession& e) { *need(out, "out") = e.aovInfo(index); });
}
PrdStatus aovDescribe(PrdSession* s, const char* name, PrdAovInfo* out) {
    return guard(s,
                 [&](EmbreeSession& e) { *need(out, "out") = e.describeAov(need(name, "name")); });
}
PrdStatus bindAov(PrdSession* s, const char* name) {
    return guard(s, [&](EmbreeSession& e) { e.bindAov(need(name, "name")); });
}
PrdStatus unbindAov(PrdSession* s, const char* name) {
    return guard(s, [&](EmbreeSession& e) { e.unbindAov(need(name, "name")); });
}
PrdStatus renderPass(PrdSession* s, int* converged) {
    return guard(s, [&](EmbreeSession& e) {
        bool c = e.renderPass();
        if (converged) *converged = c ? 1 : 0;
    });
}
PrdStatus progress(PrdSession* s, int* converged, int* completed, int* target) {
    return guard(s, [&](EmbreeSession& e) { e.progress(converged, completed, target); });
}
PrdStatus mapAov(PrdSession* s, const char* name, PrdBufferView* out) {
    return guard(s, [&](EmbreeSession& e) {
        need(out, "out");
        *out = PrdBufferView{};
        *out = e.mapAov(need(name, "name"));
    });
}
PrdStatus statCount(PrdSession* s, int* count) {
    return guard(s,
                 [&](EmbreeSession& e) { *need(count, "count") = int(e.snapshotStats().size()); });
}
PrdStatus stat(PrdSession* s, int index, const char** key, double* value) {
    return guard(s, [&](EmbreeSession& e) {
        need(key, "key");
        need(value, "value");
        // Reads the snapshot prdStatCount took; takes one if there is none yet.
        const auto& stats = e.stats().empty() ? e.snapshotStats() : e.stats();
        if (index < 0 || index >= int(stats.size()))
            throw SessionError(PRD_ERROR_NOT_FOUND, "stat index " + std::to_string(index) +
                                                        " out of range (" +
                                                        std::to_string(stats.size()) + " stats)");
        *key = stats[index].first.c_str();
        *value = stats[index].second;
    });
}
PrdStatus takeWarnings(PrdSession* s, const char** text) {
    return guard(s, [&](EmbreeSession& e) { *need(text, "text") = e.takeWarnings(); });
}

const PrdRendererApi kApi = {
    PRD_ABI_VERSION,
    sizeof(PrdRendererApi),
    create,
    destroy,
    lastError,
    openStageFile,
    openStageString,
    setAttributeNumbers,
    setAttributeString,
    setLocalTransform,
    setSettingInt,
    setSettingFloat,
    setSettingString,
    settingCount,
    settingDescriptor,
    getSetting,
    setCamera,
    getCamera,
    setResolution,
    aovCount,
    aovInfo,
    aovDescribe,
    bindAov,
    unbindAov,
    renderPass,
    progress,
    mapAov,
    statCount,
    stat,
    takeWarnings,
    addPrim,
    removePrim,
    bindMaterial,
    setRelationship,
    connectAttribute,
    setAttributeTyped,
    setFraming,
    reloadTextures,
};

}  // namespace

extern "C" const PrdRendererApi* prdEmbreeRendererApi(void) {
    return &kApi;
}
