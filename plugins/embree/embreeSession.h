// SPDX-License-Identifier: Apache-2.0
// EmbreeSession: one Embree render delegate instance as the C ABI sees it: the delegate and
// its settings, at most one open stage populated into a render index through an
// EditableSceneDelegate, a camera, a resolution, AOV buffers, and the progressive pass. It is
// RenderSession (plugins/renderSession.h) with everything a host changes after creation
// exposed. Failures throw SessionError, which the C table turns into a status and message.
#pragma once

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "plugins/abi/principled_types.h"
#include "plugins/embree/editableSceneDelegate.h"

namespace principled::usd {
class Stage;
}
namespace principled::hd {
class RenderIndex;
class RenderPass;
}  // namespace principled::hd
namespace principled::embree {
class EmbreeRenderBuffer;
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
    void setAttribute(const std::string& primPath, const std::string& attribute,
                      const EditValue& v);
    void setLocalTransform(const std::string& primPath, const double matrix[16]);

    void setSetting(const std::string& key, const SettingInput& value);
    int settingCount();
    PrdSettingDescriptor settingDescriptor(int index);
    const char* settingText(const std::string& key);

    void setCamera(const std::string& primPath);
    const std::string& camera() const;
    void setResolution(int width, int height);

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
    void open(std::unique_ptr<usd::Stage> stage);
    void populate(std::unique_ptr<usd::Stage> stage);
    void closeStage();
    void requireStage(const char* what) const;
    void allocateBuffer(const std::string& name);
    std::string cameraList() const;
    /// Stores `s` for the session's lifetime and returns its characters.
    const char* keep(const std::string& s);

    std::unique_ptr<embree::EmbreeRenderDelegate> _delegate;
    std::unique_ptr<usd::Stage> _stage;
    std::unique_ptr<hd::RenderIndex> _index;
    std::unique_ptr<EditableSceneDelegate> _scene;
    std::unique_ptr<hd::RenderPass> _pass;
    std::string _cameraRequest;  ///< empty: the default camera
    std::string _cameraPath;     ///< the camera in use while a stage is open
    int _width = 640, _height = 360;
    std::vector<std::string> _bound;                              ///< in bind order
    std::map<std::string, embree::EmbreeRenderBuffer*> _buffers;  ///< owned by the index
    // Storage behind strings returned through the C ABI (declared before _aovs, which points in).
    std::vector<std::unique_ptr<std::string>> _strings;
    std::vector<Aov> _aovs;  ///< the probed AOVs, then any other name describeAov accepted
    std::string _text;
    std::vector<std::pair<std::string, double>> _stats;
    size_t _adapterWarningsTaken = 0, _stageWarningsTaken = 0;
};

}  // namespace principled::plugins
