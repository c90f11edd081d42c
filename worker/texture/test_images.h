#pragma once

// Test helpers: image files written with OpenImageIO, scratch folders to write them in, and
// digests to name them by.

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace farm {

// Writes a width x height image of `channels` channels whose value at (x, y, c) is
// value(x, y, c) (in [0, 1] for integer types), as `format` ("png", "exr"), to `path`
// (which need not have that extension: blobs in the cache have none).
inline void WriteTestImage(const std::filesystem::path& path, const std::string& format, int width, int height,
                           int channels, OIIO::TypeDesc type, const std::function<float(int, int, int)>& value) {
  std::vector<float> pixels(std::size_t(width) * height * channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) pixels[(std::size_t(y) * width + x) * channels + c] = value(x, y, c);
  const std::string named = path.string() + "." + format;
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(named);
  OIIO::ImageSpec spec(width, height, channels, type);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the values are written as given, alpha or not
  if (!out || !out->open(named, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close())
    throw std::runtime_error("cannot write " + named + ": " + OIIO::geterror());
  std::filesystem::rename(named, path);
}

// An empty scratch folder for the running GoogleTest test, named by `prefix`, the process
// and the test (so that parallel runs do not meet).
inline std::filesystem::path FreshTestDir(const std::string& prefix, const std::string& test_name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" + test_name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A well-formed digest made of one repeated hex digit.
inline std::string TestDigest(char hex) { return "sha256:" + std::string(64, hex); }

}  // namespace farm
