// SPDX-License-Identifier: Apache-2.0
// RenderSession: what a host does to render a USD stage: open it, populate a render index
// through the scene adapter, pick a camera, bind AOV buffers, and step progressive passes.
// The CLI, tests and host bindings share it.
#pragma once

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "delegate/hd/framing.h"
#include "delegate/hd/path.h"

namespace principled::usd {
class Stage;
}
namespace principled::hd {
class RenderIndex;
class RenderPass;
class RenderDelegate;
}  // namespace principled::hd
namespace principled::adapter {
class StageEditor;
class UsdSceneDelegate;
}  // namespace principled::adapter
namespace principled::embree {
class EmbreeRenderBuffer;
class EmbreeRenderDelegate;
class EmbreeRenderPass;
}  // namespace principled::embree

namespace principled::host {

/// A problem in what the user asked for (unknown camera, bad setting): the CLI exits 1.
class UserError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SessionOptions {
    /// 0 x 0: the stage's UsdRenderSettings resolution, else 640 x 360.
    int width = 640;
    int height = 360;
    int samplesPerPixel = 64;
    int seed = 0;
    int maxDepth = 8;
    std::string camera;           ///< prim path; empty = the stage's RenderSettings camera, else the first, else a framing one
    /// Conform policy, pixel aspect ratio and data window; unset: the stage's RenderSettings
    /// (its product's over its own), else the UsdRender fallbacks.
    std::optional<hd::Framing> framing;
    std::string shadingModel = "disney";
    std::string sampler = "sobol";  ///< sobol | independent
    int refineLevel = -1;           ///< subdivision level for every mesh; -1 = adaptive
    float noiseThreshold = 0.0f;    ///< adaptive sampling: relative standard error to stop at
    /// Any render setting by key ("mis" = "0", "deltaRoughness" = "0.01"...): integers, then
    /// numbers, else tokens. Unknown keys are a UserError.
    std::map<std::string, std::string> settings;
    /// Sample indices [first, end) to render (end <= first: all of [0, samplesPerPixel)).
    int sampleRangeFirst = 0, sampleRangeEnd = 0;
    /// AOVs to render besides color ("normal", "primId", ... or "all").
    std::vector<std::string> aovs;
    double time = std::numeric_limits<double>::quiet_NaN();
    /// A render delegate the host keeps across sessions (the C ABI's, whose settings outlive a
    /// stage): its settings are used as they are and the setting fields above are ignored.
    /// nullptr: the session creates and owns one configured from these options.
    embree::EmbreeRenderDelegate* renderDelegate = nullptr;
};

class RenderSession {
public:
    /// Opens a .usda file (throws usd::Error on unreadable or malformed input).
    static std::unique_ptr<RenderSession> openFile(const std::string& path,
                                                   const SessionOptions& options);
    /// Parses USDA text; displayName is used in error locations.
    static std::unique_ptr<RenderSession> openString(const std::string& text,
                                                     const std::string& displayName,
                                                     const SessionOptions& options);
    ~RenderSession();

    /// Runs one progressive pass; returns true once converged.
    bool step();
    bool converged() const;
    int completedSamples() const;
    int targetSamples() const;

    int width() const { return _options.width; }
    int height() const { return _options.height; }
    /// The color AOV: RGBA floats, top row first (alpha 1 where geometry was hit).
    const float* color() const;

    struct AovImage {
        std::string name;
        int components = 0;
        bool isInt = false;       ///< int32 pixels (IDs), else float
        const void* pixels = nullptr;
    };
    /// Every bound AOV (color first), resolved after the last step().
    std::vector<AovImage> aovs() const;

    /// Scene and delegate problems found so far (each once).
    std::vector<std::string> takeWarnings();
    std::map<std::string, double> stats() const;
    embree::EmbreeRenderPass* pass() const;
    hd::RenderIndex* index() const { return _index.get(); }
    const usd::Stage& stage() const { return *_stage; }
    embree::EmbreeRenderDelegate* delegate() const { return _delegate; }
    /// The render buffer of an AOV (nullptr if not bound).
    embree::EmbreeRenderBuffer* buffer(const std::string& aov) const;
    const std::string& cameraPath() const { return _cameraPath; }
    /// How the image frames the camera (SessionOptions::framing, or the stage's).
    const hd::Framing& framing() const { return _framing; }
    /// The pixels' width / height as rendered: the framing's, or under adjustPixelAspectRatio
    /// what maps the camera's aperture onto the image (written to EXR headers).
    float pixelAspectRatio() const { return _pixelAspectRatio; }
    /// The stage's camera prims (a framing camera is added only when it has none).
    const std::vector<hd::Path>& cameras() const;
    /// Renders through camera `primPath` from the next step ("": the first camera, else the
    /// framing camera). UserError naming the cameras when it is not one.
    void setCamera(const std::string& primPath);
    /// New image size (1..32768 each); every bound buffer is reallocated.
    void setResolution(int width, int height);
    /// The host's framing from the next step (nullopt: the stage's RenderSettings framing).
    void setFraming(const std::optional<hd::Framing>& framing);
    /// Texture files edited on disk since they were read (onlyChanged: by modification time or
    /// size; else all of them) are read again from the next step: the render delegate's
    /// texture cache drops them and every material and light is re-synced. Returns whether
    /// anything is re-read (the image then restarts).
    bool reloadTextures(bool onlyChanged = true);
    /// Binds one more AOV (no-op when bound; UserError for an unknown name) or unbinds one
    /// (color stays bound).
    void bindAov(const std::string& name);
    void unbindAov(const std::string& name);

    /// Host edits of the open stage (set attributes, transforms, add/remove prims, bindings):
    /// each marks only the dirty bits it implies; the next step() syncs just those.
    adapter::StageEditor& editor() { return *_editor; }
    adapter::UsdSceneDelegate& sceneDelegate() const { return *_sceneDelegate; }

private:
    RenderSession(std::unique_ptr<usd::Stage> stage, const SessionOptions& options);
    void setup();
    void applySettings();
    void chooseCamera(const std::string& request);
    /// The camera's window for this image (the camera, resolution or framing changed): the
    /// dicing view of adaptive subdivision and the rendered pixel aspect ratio.
    void updateCameraWindow();
    embree::EmbreeRenderBuffer* allocate(const std::string& name);

    SessionOptions _options;
    std::unique_ptr<usd::Stage> _stage;
    std::unique_ptr<embree::EmbreeRenderDelegate> _ownedDelegate;
    embree::EmbreeRenderDelegate* _delegate = nullptr;
    std::unique_ptr<hd::RenderIndex> _index;
    std::unique_ptr<adapter::UsdSceneDelegate> _sceneDelegate;
    std::unique_ptr<adapter::StageEditor> _editor;
    std::unique_ptr<hd::RenderPass> _pass;
    embree::EmbreeRenderBuffer* _color = nullptr;
    std::vector<std::pair<std::string, embree::EmbreeRenderBuffer*>> _buffers;
    std::string _cameraPath;
    hd::Framing _framing;
    hd::Framing _stageFraming;  ///< what the stage's RenderSettings ask for
    float _pixelAspectRatio = 1.0f;
    std::vector<std::string> _notes;  ///< the session's own warnings (render settings)
    size_t _adapterWarningsTaken = 0;
    size_t _stageWarningsTaken = 0;
};

}  // namespace principled::host
