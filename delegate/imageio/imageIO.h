// SPDX-License-Identifier: Apache-2.0
// Image I/O behind a backend that is loaded on first use.
//
// OpenImageIO pulls in ~270 shared libraries (ffmpeg, OpenVDB, GDAL, DCMTK, ...) whose
// relocation costs ~0.27 s of CPU at every process start. Nothing in the project links it:
// every image read (textures, light images, checkpoints) and every write other than the EXR/PNG
// output (nativeWriter.h: OpenEXRCore and libpng) goes through imageio::backend(), which dlopen()s libprincipled_oiio.so
// (the only module that links OpenImageIO) the first time it is needed. `principled info`,
// `principled plugins` and a render of a scene without image files never load it.
//
// The backend is searched for (first hit wins):
//   1. $PRINCIPLED_IMAGEIO_BACKEND (a full path to the module),
//   2. next to the executable's lib folder (<exe dir>/../lib/) and relative to the shared
//      object holding this code (a plugin in lib/principled/plugins/NAME/, or lib/ itself),
//   3. the build tree and the install prefix configured by CMake,
//   4. the default dynamic-loader search (LD_LIBRARY_PATH, ...).
// It is never unloaded (OpenImageIO's texture system lives as long as the process).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace principled::imageio {

/// Bumped whenever the classes below change layout or meaning.
constexpr int kAbiVersion = 2;

enum class PixelType : int { UInt8, UInt16, UInt32, Half, Float, Other };

/// The parts of an image's description the project uses.
struct ImageSpec {
    int width = 0, height = 0, channels = 0;
    /// Write: the file's pixel type (and the type of the data passed in). Read: the file's.
    PixelType format = PixelType::Float;
    int bitsPerChannel = 0;                 ///< read: bits of one channel value in the file
    std::vector<std::string> channelNames;  ///< write: empty = the format's default (R,G,B,A)
    int alphaChannel = -1;                  ///< write: -1 = none
    std::string fileFormat;                 ///< read: OpenImageIO's format name ("openexr", "png")
    /// Metadata. Write: strings stay strings, numbers are written as int when integral, else
    /// float. Read: every string attribute, and every int/float one as a number.
    std::map<std::string, std::string> strings;
    std::map<std::string, double> numbers;

    std::string string(const std::string& name, const std::string& fallback = "") const {
        auto it = strings.find(name);
        return it == strings.end() ? fallback : it->second;
    }
    double number(const std::string& name, double fallback = 0.0) const {
        auto it = numbers.find(name);
        return it == numbers.end() ? fallback : it->second;
    }
};

/// An open image file (the first subimage, level 0).
class ImageReader {
  public:
    virtual ~ImageReader() = default;
    virtual const ImageSpec& spec() const = 0;
    /// Reads all pixels, converted to `as` (UInt8, UInt16, UInt32 or Float; 8/16-bit values
    /// become [0,1] floats), interleaved, top row first, `channels` per pixel (the first ones).
    virtual bool read(PixelType as, int channels, void* pixels) = 0;
    virtual std::string error() = 0;
};

/// OpenImageIO's process-wide texture system (mip-mapped, tiled, with a memory limit).
class TextureSystem {
  public:
    /// Applied to the one system of the process (the last call wins).
    virtual void configure(float maxMemoryMB, int maxOpenFiles, bool autoMip) = 0;
    /// Resolves a file to a handle; null with *error (OpenImageIO's message, may be empty).
    /// *spec gets the file's size, channels, pixel type, format name and metadata.
    virtual void* open(const std::string& path, ImageSpec* spec, std::string* error) = 0;
    /// Filtered lookup at OpenImageIO's (s, t) (t down from the top row) with derivatives;
    /// wrap: 0 black, 1 clamp, 2 periodic, 3 mirror. Writes `channels` values (<= 4).
    virtual bool lookup(void* handle, int wrapS, int wrapT, float s, float t, float dsdx,
                        float dtdx, float dsdy, float dtdy, int channels, float* out) = 0;
    virtual void invalidateAll() = 0;
    /// Drops one file's tiles and handle state; force false: only when the file's modification
    /// time is newer than when the system opened it.
    virtual void invalidate(const std::string& path, bool force) = 0;
    virtual size_t memoryUsed() = 0;

  protected:
    ~TextureSystem() = default;  // owned by the backend, never deleted
};

/// What libprincipled_oiio.so provides.
class Backend {
  public:
    /// Opens a file for reading; null with *error naming the reason.
    virtual std::unique_ptr<ImageReader> open(const std::string& path, std::string* error) = 0;
    /// open() as the texture system reads a file: colours with alpha are left unassociated
    /// (straight, as UsdPreviewSurface expects), where open() premultiplies PNG/TIFF colours.
    virtual std::unique_ptr<ImageReader> openTexture(const std::string& path,
                                                     std::string* error) = 0;
    /// Writes `pixels` (spec.channels values of spec.format per pixel, top row first) to path
    /// in the format that `formatFrom`'s extension names (the path itself when empty, so a
    /// temporary file can be written under another name). False with *error (no path).
    virtual bool write(const std::string& path, const std::string& formatFrom,
                       const ImageSpec& spec, const void* pixels, std::string* error) = 0;
    virtual TextureSystem& textureSystem() = 0;
    virtual const char* description() const = 0;  ///< "OpenImageIO 2.4.x"

  protected:
    ~Backend() = default;  // lives as long as the process
};

/// Loads the backend on first call (thread-safe); later calls return the same one. Null when it
/// cannot be loaded, with *error (if given) saying where it was searched and why it failed.
Backend* backend(std::string* error = nullptr);

/// The backend if some earlier call loaded it, else null (never loads it).
Backend* loadedBackend();

/// The path the backend was loaded from (empty before).
std::string backendPath();

/// Opens a texture file as the backend's openTexture() does (straight alpha). PNG files are
/// decoded natively with libpng when `nativePng` (pngReader.h), without loading the backend;
/// anything else, and any PNG libpng cannot read, goes to the backend. Null with *error.
std::unique_ptr<ImageReader> openTexture(const std::string& path, std::string* error,
                                         bool nativePng = true);

}  // namespace principled::imageio

// The module's entry points (extern "C", looked up with dlsym).
extern "C" {
using PrincipledImageioAbiVersionFn = int (*)();
using PrincipledImageioBackendFn = principled::imageio::Backend* (*)();
}
