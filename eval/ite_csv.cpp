#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "eval/trajectory_eval.h"

namespace sb {

void writeIteCsv(const std::string& path, const AteResult& ate) {
  const size_t n = ate.timestamps.size();
  if (ate.errors.size() != n || ate.unalignedErrors.size() != n) {
    throw Error("writeIteCsv: the ATE result holds " + std::to_string(n) + " timestamps but " +
                std::to_string(ate.errors.size()) + " aligned and " +
                std::to_string(ate.unalignedErrors.size()) +
                " unaligned errors; pass a result of computeAte");
  }
  std::ofstream out(path);
  if (!out)
    throw Error("cannot write ITE CSV '" + path + "': check that the directory exists and is writable");
  out << "timestamp,ate_error_m,unaligned_error_m\n";
  char line[128];
  for (size_t i = 0; i < n; ++i) {
    std::snprintf(line, sizeof line, "%.6f,%.9f,%.9f\n", ate.timestamps[i], ate.errors[i],
                  ate.unalignedErrors[i]);
    out << line;
  }
  out.flush();
  if (!out) throw Error("writing ITE CSV '" + path + "' failed (disk full?)");
}

}  // namespace sb
