#pragma once

#include <stdexcept>

namespace farm {

// Thrown when image bytes cannot be read or do not describe what was expected (tiles come
// from other machines, so they are untrusted input). The message says what was wrong.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace farm
