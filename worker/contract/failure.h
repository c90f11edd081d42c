#pragma once

// Errors that know their failure kind (FailTaskRequest.kind, FailureKind in rules.proto),
// so that the coordinator can fail a job at once for bad input instead of retrying it like
// a network blip:
//
//   BadInputError     the scene, an asset it names or the task's spec is wrong (SceneError
//                     derives from it): every worker would fail the same way
//   UnsupportedError  the task asks for something this worker cannot do
//   std::bad_alloc, a std::system_error for a full disk or quota, or out of memory
//                     -> RESOURCE_EXHAUSTED
//   anything else (RPC and blob transfer errors included) -> TRANSIENT

#include <exception>
#include <stdexcept>
#include <string>

#include "renderfarm/v1/rules.pb.h"

namespace farm {

class TaskError : public std::runtime_error {
 public:
  TaskError(renderfarm::v1::FailureKind kind, const std::string& what)
      : std::runtime_error(what), kind_(kind) {}
  renderfarm::v1::FailureKind kind() const noexcept { return kind_; }

 private:
  renderfarm::v1::FailureKind kind_;
};

class BadInputError : public TaskError {
 public:
  explicit BadInputError(const std::string& what)
      : TaskError(renderfarm::v1::FAILURE_KIND_BAD_INPUT, what) {}
};

class UnsupportedError : public TaskError {
 public:
  explicit UnsupportedError(const std::string& what)
      : TaskError(renderfarm::v1::FAILURE_KIND_UNSUPPORTED, what) {}
};

// The kind of failure `e` is, by the table above.
renderfarm::v1::FailureKind FailureKindOf(const std::exception& e);

}  // namespace farm
