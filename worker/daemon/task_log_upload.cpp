#include "daemon/task_log_upload.h"

#include <cstdint>
#include <exception>

#include "contract/tasks.h"
#include "daemon/log.h"

namespace farm {

std::optional<renderfarm::v1::Artifact> UploadTaskLog(std::optional<TaskLog>& log, const std::string& task_id,
                                                      const LogUploader& upload) {
  const std::string text = log ? log->Text() : "";
  log.reset();  // The upload's own lines and the report's are not the task's.
  try {
    renderfarm::v1::Artifact a;
    a.set_name(contract::ArtifactName(renderfarm::v1::ARTIFACT_KIND_TASK_LOG));
    a.set_digest(upload(text));
    a.set_size_bytes(static_cast<std::int64_t>(text.size()));
    return a;
  } catch (const std::exception& e) {
    Log(LogLevel::kWarn, "cannot upload the task log; reporting without it", {{"task", task_id}, {"err", e.what()}});
    return std::nullopt;
  }
}

}  // namespace farm
