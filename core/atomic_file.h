#pragma once
// Whole or not at all: an output file (model.png, mesh.ply, a depth frame) is written to a temporary sibling
// and renamed over its name only once every byte was written, so a full disk or an I/O error never leaves a
// truncated file behind under the real name. The temporary is made by core/exclusive_file.h (a new name,
// O_EXCL|O_NOFOLLOW): no symlink or hard link made beforehand in the directory is ever written through.

#include <cstdio>
#include <functional>
#include <string>

namespace sb {

// Calls `write(file, temporary)` with a stdio stream on a new temporary beside `path` (`temporary` is its
// path, for messages), then flushes it and renames it over `path`. When `write` throws, or the flush or the
// rename fails, the temporary is removed, `path` keeps what it had, and sb::Error names the file and the
// system's reason (sb::DiskFullError for a full disk).
void writeFileAtomically(const std::string& path,
                         const std::function<void(std::FILE* file, const std::string& temporary)>& write);

}  // namespace sb
