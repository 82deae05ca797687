#pragma once
// Whole or not at all: an output file (model.png, mesh.ply, a depth frame) is written to a temporary sibling
// and renamed over its name only once every byte was written, so a full disk or an I/O error never leaves a
// truncated file behind under the real name.

#include <functional>
#include <string>

namespace sb {

// The temporary sibling of `path` that writeFileAtomically() fills ("<path>.tmp").
std::string temporaryPathFor(const std::string& path);

// Calls `write(temporary)`, then renames the temporary over `path`. When `write` throws, or the rename fails,
// the temporary is removed, `path` keeps what it had, and sb::Error names `path` and the system's reason.
void writeFileAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);

}  // namespace sb
