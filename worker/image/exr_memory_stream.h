#pragma once

// OpenEXR streams over memory, so tiles and images go to and from the blob store without
// touching the filesystem. Internal to image/: only .cpp files include this.

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace farm {

// Appends to (or overwrites inside, after a seek) a string the caller owns.
class ExrStringOStream final : public Imf::OStream {
 public:
  explicit ExrStringOStream(std::string& out) : Imf::OStream("<memory>"), out_(out) {}

  void write(const char c[], int n) override;
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t pos) override { position_ = pos; }

 private:
  std::string& out_;
  uint64_t position_ = 0;
};

// Reads a view of bytes the caller keeps alive. Reading past the end throws, as OpenEXR
// expects of a truncated file.
class ExrMemoryIStream final : public Imf::IStream {
 public:
  explicit ExrMemoryIStream(std::string_view bytes) : Imf::IStream("<memory>"), bytes_(bytes) {}

  bool isMemoryMapped() const override { return true; }
  bool read(char c[], int n) override;
  char* readMemoryMapped(int n) override;
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t pos) override { position_ = pos; }
  void clear() override {}

 private:
  void Need(int n) const;

  std::string_view bytes_;
  uint64_t position_ = 0;
};

// A scanline EXR of header's data window with the pixels of frame_buffer, in memory; a
// failure is an ImageError "cannot encode <what>: ...".
std::string EncodeExr(const Imf::Header& header, const Imf::FrameBuffer& frame_buffer,
                      const std::string& what);

}  // namespace farm
