#include "controller/controller.h"

namespace sb {

std::vector<std::string> triggerNames(uint32_t triggers) {
  static const char* const names[] = {"bootstrap", "integral", "derivative_up", "derivative_down",
                                      "surface",   "correction", "hold",        "budget",
                                      "retrack",   "unconstrained", "doubt",    "skip_integrate"};
  std::vector<std::string> out;
  for (uint32_t bit = 0; bit < sizeof(names) / sizeof(names[0]); ++bit)
    if (triggers & (1u << bit)) out.emplace_back(names[bit]);
  return out;
}

}  // namespace sb
