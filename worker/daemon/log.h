#pragma once

#include <string_view>

namespace farm {

// Writes one line to stderr, prefixed with the UTC time and "farm-worker:". Lines from
// different threads never interleave.
void LogLine(std::string_view message);

}  // namespace farm
