#include "contract/failure.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <new>
#include <system_error>

namespace farm {
namespace {

namespace pb = renderfarm::v1;

TEST(FailureKindOf, MapsEachErrorToTheKindTheCoordinatorActsOn) {
  EXPECT_EQ(FailureKindOf(BadInputError("shapes[0].mesh: ...")), pb::FAILURE_KIND_BAD_INPUT);
  EXPECT_EQ(FailureKindOf(UnsupportedError("no such task kind")), pb::FAILURE_KIND_UNSUPPORTED);
  EXPECT_EQ(FailureKindOf(std::bad_alloc()), pb::FAILURE_KIND_RESOURCE_EXHAUSTED);
  EXPECT_EQ(FailureKindOf(std::system_error(ENOSPC, std::generic_category(), "write")),
            pb::FAILURE_KIND_RESOURCE_EXHAUSTED);
  EXPECT_EQ(FailureKindOf(std::filesystem::filesystem_error(
                "rename", std::make_error_code(std::errc::no_space_on_device))),
            pb::FAILURE_KIND_RESOURCE_EXHAUSTED);
  EXPECT_EQ(FailureKindOf(std::system_error(EACCES, std::generic_category(), "open")),
            pb::FAILURE_KIND_TRANSIENT);
  EXPECT_EQ(FailureKindOf(std::runtime_error("cannot download blob")), pb::FAILURE_KIND_TRANSIENT);
}

TEST(FailureKindOf, DerivedErrorsKeepTheirKind) {
  struct MeshError : BadInputError {
    using BadInputError::BadInputError;
  };
  EXPECT_EQ(FailureKindOf(MeshError("x")), pb::FAILURE_KIND_BAD_INPUT);
}

}  // namespace
}  // namespace farm
