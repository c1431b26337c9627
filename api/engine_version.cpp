#include "api/engine_version.h"

#include <stdexcept>
#include <string>

#include "engine/contact/pair_kernel.h"

namespace granulab::api {

const char* engine_version() {
  static const std::string version = [] {
    std::string kernel;
    try {
      kernel = resolve_pair_kernel("");
    } catch (const std::invalid_argument&) {  // a GRANULAB_KERNEL the CPU lacks: the runs refuse it themselves
      kernel = best_pair_kernel();
    }
    return std::string(engine_source_version()) + "." + kernel;
  }();
  return version.c_str();
}

}  // namespace granulab::api
