// SPDX-License-Identifier: Apache-2.0
// The image files `principled render` writes (-o, --split): checked before the scene is
// loaded, and written each to a temporary name in its directory renamed into place, so an
// output is either the previous file, or complete.
#pragma once

#include <string>
#include <vector>

namespace principled::host {
class RenderSession;
}

namespace principled::tools {

/// ".exr" or ".png" whatever the case ("a.EXR" is an EXR), else "".
std::string outputFormat(const std::string& path);
/// What stops `path` from being written ("" when nothing does): an extension other than
/// .exr/.png, a directory that cannot be created or written into, a directory at the path.
/// Creates missing parent directories. image: an -o output (else the --stats file).
std::string checkWritable(const std::string& path, bool image);
/// Writes the session's AOVs to every output (an EXR gets every AOV as layers, or with split
/// one file per AOV, OUT.AOV.exr with ':' in AOV names written as '_'; a PNG the color), each
/// through a temporary file renamed into place. A failed file does not stop the others;
/// returns one message per failure.
std::vector<std::string> writeOutputs(const host::RenderSession& session, const std::vector<std::string>& outputs,
                                      bool split);

}  // namespace principled::tools
