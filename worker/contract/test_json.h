#pragma once

// For tests (not linked into the worker): a message written as protobuf JSON, which reads
// better than a page of setters.

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <string>

namespace farm::testing {

template <class M>
M FromJson(const std::string& json) {
  M m;
  const auto status = google::protobuf::util::JsonStringToMessage(json, &m);
  EXPECT_TRUE(status.ok()) << status.ToString() << "\n" << json;
  return m;
}

}  // namespace farm::testing
