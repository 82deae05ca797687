#pragma once
// The frame list of a TUM-layout sequence: `depth.txt` (`timestamp filename` per line) or, for sequences
// distributed without one (ICL-NUIM's TUM-compatible archives), `associations.txt` (`timestamp file
// timestamp file` per line; the depth pair is the one whose file lies under `depth/`). '#' starts a comment
// line; blank lines and CR line ends are accepted.

#include <cstddef>
#include <string>
#include <vector>

namespace sb {

struct TumIndexEntry {
  size_t line = 0;       // 1-based line number in the index file
  double timestamp = 0;  // seconds
  std::string file;      // as written, relative to the sequence directory unless absolute
};

// Reads and checks an index: malformed lines, timestamps that are not finite numbers or do not strictly
// increase, and an index without frames throw sb::Error naming the file and line.
std::vector<TumIndexEntry> readTumIndex(const std::string& path, bool associations);

}  // namespace sb
