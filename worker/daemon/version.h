#pragma once

// The worker's name and version: what it registers as, and what the EXRs it composites
// name as their software.

namespace farm {

inline constexpr char kWorkerVersion[] = "farm-worker 0.1.0";

}  // namespace farm
