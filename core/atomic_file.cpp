#include "core/atomic_file.h"

#include "core/exclusive_file.h"

namespace sb {

void writeFileAtomically(const std::string& path,
                         const std::function<void(std::FILE* file, const std::string& temporary)>& write) {
  TemporaryFile temporary(path);  // removed by its destructor unless committed
  write(temporary.stream(), temporary.path());
  temporary.commit();
}

}  // namespace sb
