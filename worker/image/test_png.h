#pragma once

// For tests (not linked into the worker): decoding the PNG previews the image code writes.

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace farm::testing {

// Decodes 8-bit RGBA PNG bytes to their stored values (straight alpha: OpenImageIO is told
// not to premultiply) and their size; a PNG that does not decode, or is not 8-bit RGBA, is
// a test failure.
inline std::vector<std::uint8_t> ReadPng(const std::string& png, int* width, int* height) {
  OIIO::Filesystem::IOMemReader reader(png.data(), png.size());
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  // With a config, OpenImageIO 2.4 only sees the proxy if the config names it too.
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open("preview.png", &config, &reader);
  if (!in) {
    ADD_FAILURE() << OIIO::geterror();
    return {};
  }
  *width = in->spec().width;
  *height = in->spec().height;
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  EXPECT_EQ(in->spec().nchannels, 4);
  std::vector<std::uint8_t> read(static_cast<std::size_t>(*width) * *height * 4);
  EXPECT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, read.data()));
  return read;
}

}  // namespace farm::testing
