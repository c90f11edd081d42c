#pragma once

// The whole of a file, as bytes: what the daemon's TLS CA and the tests' vectors read.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace farm {

// Reads the file at path; throws std::runtime_error naming it if it cannot be read.
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read " + path.string());
  return bytes.str();
}

}  // namespace farm
