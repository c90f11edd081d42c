#pragma once

// How a task's log goes with its report: the log is ended, uploaded as "task.log", and
// named in the report; an upload that fails is logged and the report goes without the log,
// since a log must never fail its task. Apart from worker.cpp so that it can be tested
// without a coordinator. Internal to daemon/.

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "daemon/task_log.h"
#include "renderfarm/v1/job.pb.h"

namespace farm {

// Uploads bytes and returns their digest (BlobClient::Upload); may throw.
using LogUploader = std::function<std::string(std::string_view bytes)>;

// Ends `log` (it keeps no line after this) and uploads its text with upload: the artifact
// to report, or nullopt if the upload threw, which is logged naming task_id.
std::optional<renderfarm::v1::Artifact> UploadTaskLog(std::optional<TaskLog>& log, const std::string& task_id,
                                                      const LogUploader& upload);

}  // namespace farm
