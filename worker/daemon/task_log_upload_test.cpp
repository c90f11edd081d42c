#include "daemon/task_log_upload.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "daemon/log.h"

namespace farm {
namespace {

TEST(UploadTaskLog, UploadsTheLinesSoFarAsTaskLogAndEndsTheLog) {
  std::optional<TaskLog> log(std::in_place, 64 * 1024);
  Log(LogLevel::kInfo, "task started", {{"task", "J.3"}});
  std::string uploaded;
  const auto artifact = UploadTaskLog(log, "J.3", [&](std::string_view bytes) {
    uploaded = bytes;
    Log(LogLevel::kInfo, "uploading");  // not the task's line
    return std::string("sha256:") + std::string(64, 'a');
  });
  ASSERT_TRUE(artifact.has_value());
  EXPECT_EQ(artifact->name(), "task.log");
  EXPECT_EQ(artifact->digest(), "sha256:" + std::string(64, 'a'));
  EXPECT_EQ(artifact->size_bytes(), static_cast<std::int64_t>(uploaded.size()));
  EXPECT_NE(uploaded.find("msg=\"task started\" task=J.3\n"), std::string::npos) << uploaded;
  EXPECT_EQ(uploaded.find("uploading"), std::string::npos) << uploaded;
  EXPECT_FALSE(log.has_value());
}

// A log whose upload fails is left out of the report, which still goes: the failure is a
// warning, not the task's failure.
TEST(UploadTaskLog, AFailedUploadIsAWarningAndNoLog) {
  TaskLog watcher(64 * 1024);  // sees the warning
  std::optional<TaskLog> log(std::in_place, 64 * 1024);
  std::optional<renderfarm::v1::Artifact> artifact;
  EXPECT_NO_THROW(artifact = UploadTaskLog(log, "J.4", [](std::string_view) -> std::string {
                    throw std::runtime_error("UploadBlob: connection refused");
                  }));
  EXPECT_FALSE(artifact.has_value());
  EXPECT_FALSE(log.has_value());
  const std::string seen = watcher.Text();
  EXPECT_NE(seen.find("level=WARN msg=\"cannot upload the task log; reporting without it\" task=J.4 "
                      "err=\"UploadBlob: connection refused\""),
            std::string::npos)
      << seen;
}

}  // namespace
}  // namespace farm
