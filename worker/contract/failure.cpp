#include "contract/failure.h"

#include <cerrno>
#include <new>
#include <system_error>

namespace farm {

renderfarm::v1::FailureKind FailureKindOf(const std::exception& e) {
  if (const auto* task = dynamic_cast<const TaskError*>(&e)) return task->kind();
  if (dynamic_cast<const std::bad_alloc*>(&e)) return renderfarm::v1::FAILURE_KIND_RESOURCE_EXHAUSTED;
  if (const auto* system = dynamic_cast<const std::system_error*>(&e)) {
    const std::error_code code = system->code();
    if (code.category() == std::generic_category() || code.category() == std::system_category()) {
      switch (code.value()) {
        case ENOSPC:
        case EDQUOT:
        case ENOMEM:
        case EMFILE:
        case ENFILE:
          return renderfarm::v1::FAILURE_KIND_RESOURCE_EXHAUSTED;
        default:
          break;
      }
    }
  }
  return renderfarm::v1::FAILURE_KIND_TRANSIENT;
}

}  // namespace farm
