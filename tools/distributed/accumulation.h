// SPDX-License-Identifier: Apache-2.0
// Accumulation: everything a render of a sample range leaves behind (per AOV sums, first-hit
// values and sample counts; per-pixel luminance statistics), so partial renders of disjoint
// sample ranges can be merged (MPI ranks) or saved and restored (checkpoints).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "delegate/pixelStats.h"

namespace principled::host {
class RenderSession;
}

namespace principled::tools::distributed {

struct AovAccumulation {
    std::string name;
    int components = 0;
    bool isInt = false;        ///< int32 first-hit values (IDs)
    bool multiSampled = true;  ///< sums (mean at resolve) rather than the first hit
    std::vector<double> sums;  ///< float formats: sums or first-hit values
    std::vector<int32_t> ints;
    std::vector<int32_t> counts;
};

struct Accumulation {
    int width = 0, height = 0;
    int completedSamples = 0;  ///< samples per pixel accumulated
    std::vector<AovAccumulation> aovs;
    /// The render pass's per-pixel statistics and pass state (delegate/pixelStats.h).
    embree::PixelStats stats;

    /// Takes the session's accumulation (after at least one step(), or zeros before).
    static Accumulation capture(const host::RenderSession& session);
    /// Restores it into a session of the same shape that has run at least one step(), and
    /// resolves every buffer. Returns false if the shapes differ.
    bool applyTo(host::RenderSession& session) const;
    /// Adds a later range (in sample-index order): sums and counts add, first-hit values are
    /// kept from *this where it has a hit, else taken from next. Shapes must match.
    bool merge(const Accumulation& next);
    bool sameShape(const Accumulation& other) const;

    /// Flat bytes for MPI (the receiver knows the shape from its own capture()).
    std::vector<char> pack() const;
    bool unpack(const std::vector<char>& bytes);
    size_t packedSize() const;
};

/// Checkpoint identity, stored as EXR metadata and checked on --resume.
struct CheckpointInfo {
    std::string sceneHash;
    /// What the scene was read from, one file a line: "layer HASH PATH" for every layer of the
    /// composed stage, "file SIZE:MTIME PATH" for every other file its attributes name
    /// (textures, IES profiles); names the file that changed when a resume is refused.
    std::string sceneFiles;
    std::string settings;   ///< canonical "key=value;..." of everything that changes the image
    int rangeFirst = 0, rangeEnd = 0;  ///< the sample range this accumulation belongs to
    int rank = 0, ranks = 1;           ///< informational
};

/// Writes a checkpoint atomically (temp file + rename) as an EXR of UINT channels holding the
/// exact bits (doubles as lo/hi words) plus principled:* metadata. Returns false with *error.
bool writeCheckpoint(const std::string& path, const Accumulation& acc, const CheckpointInfo& info,
                     std::string* error);
/// Reads a checkpoint into acc (shape taken from the file). Returns false with *error.
bool readCheckpoint(const std::string& path, Accumulation* acc, CheckpointInfo* info,
                    std::string* error);

/// 64-bit FNV-1a of bytes, as 16 hex digits.
std::string hashBytes(const std::string& bytes);

}  // namespace principled::tools::distributed
