// SPDX-License-Identifier: Apache-2.0
// EmbreeSession: one Embree render delegate instance as the C ABI sees it: the delegate and
// its settings (kept across stages), and at most one open stage as a host::RenderSession
// (plugins/renderSession.h: index, scene adapter, camera, AOV buffers, progressive pass, and
// the adapter::StageEditor for host edits). This layer only keeps what outlives a stage
// (settings, camera request, resolution, AOV bindings) and turns every failure into
// SessionError, which the C table turns into a status and message.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "delegate/hd/framing.h"
#include "plugins/abi/principled_types.h"

namespace principled::adapter {
struct EditValue;
}
namespace principled::host {
class RenderSession;
}
namespace principled::embree {
class EmbreeRenderDelegate;
}  // namespace principled::embree

namespace principled::plugins {

class SessionError : public std::runtime_error {
  public:
    SessionError(PrdStatus status, const std::string& message)
        : std::runtime_error(message), status(status) {}
    PrdStatus status;
};

/// A setting value from the host: exactly one of int, float, string.
struct SettingInput {
    PrdValueType type = PRD_TYPE_NONE;
    long long i = 0;
    double f = 0.0;
    std::string s;
};

class EmbreeSession {
  public:
    EmbreeSession();
    ~EmbreeSession();

    void openFile(const std::string& path);
    void openString(const std::string& text, const std::string& displayName);

    // Host edits (adapter::StageEditor on the open stage).
    void setAttribute(const std::string& primPath, const std::string& attribute,
                      const adapter::EditValue& v, const std::string& typeName = "");
    void setLocalTransform(const std::string& primPath, const double matrix[16]);
    void addPrim(const std::string& primPath, const std::string& typeName);
    void removePrim(const std::string& primPath);
    void bindMaterial(const std::string& primPath, const std::string& materialPath);
    void setRelationship(const std::string& primPath, const std::string& name,
                         const std::vector<std::string>& targets);
    void connect(const std::string& primPath, const std::string& attribute,
                 const std::string& source);

    void setSetting(const std::string& key, const SettingInput& value);
    int settingCount();
    PrdSettingDescriptor settingDescriptor(int index);
    const char* settingText(const std::string& key);

    void setCamera(const std::string& primPath);
    const std::string& camera() const;
    void setResolution(int width, int height);
    /// conformPolicy null: the stage's framing; otherwise validated (INVALID_ARGUMENT naming the value).
    void setFraming(const char* conformPolicy, double pixelAspectRatio, const double* dataWindowNDC);
    /// RenderSession::reloadTextures on the open stage (NO_STAGE without one).
    bool reloadTextures(bool onlyChanged);

    int aovCount() const { return static_cast<int>(_aovs.size()); }
    PrdAovInfo aovInfo(int index) const;
    PrdAovInfo describeAov(const std::string& name);
    void bindAov(const std::string& name);
    void unbindAov(const std::string& name);

    bool renderPass();
    void progress(int* converged, int* completed, int* target) const;
    PrdBufferView mapAov(const std::string& name);

    /// Takes a new snapshot of the delegate's stats; stats() reads the last one.
    const std::vector<std::pair<std::string, double>>& snapshotStats();
    const std::vector<std::pair<std::string, double>>& stats() const { return _stats; }
    const char* takeWarnings();

  private:
    struct Aov {
        const char* name = nullptr;  ///< in _strings
        PrdFormat format = PRD_FORMAT_INVALID;
        int channels = 0;
        bool multiSampled = true;
    };
    template <typename F>
    void open(F&& makeSession);
    host::RenderSession& requireStage(const char* what) const;
    template <typename F>
    void edit(const char* what, F&& f);
    std::string cameraList() const;
    /// Stores `s` for the session's lifetime and returns its characters.
    const char* keep(const std::string& s);

    // The delegate outlives stages, so settings set before or between opens are kept.
    std::unique_ptr<embree::EmbreeRenderDelegate> _delegate;
    std::unique_ptr<host::RenderSession> _session;  ///< the open stage, if any
    std::string _cameraRequest;                     ///< empty: the default camera
    int _width = 640, _height = 360;
    std::optional<hd::Framing> _framing;  ///< the host's; nullopt = the stage's
    std::vector<std::string> _bound;  ///< in bind order
    // Storage behind strings returned through the C ABI (declared before _aovs, which points in).
    std::vector<std::unique_ptr<std::string>> _strings;
    std::vector<Aov> _aovs;  ///< the probed AOVs, then any other name describeAov accepted
    std::string _text;
    std::vector<std::pair<std::string, double>> _stats;
};

}  // namespace principled::plugins
