#include "image/exr_memory_stream.h"

#include <Iex.h>
#include <OpenEXR/ImfOutputFile.h>

#include <cstring>
#include <exception>

#include "image/image_error.h"

namespace farm {

void ExrStringOStream::write(const char c[], int n) {
  if (n <= 0) return;
  const auto end = position_ + static_cast<uint64_t>(n);
  if (end > out_.size()) out_.resize(end);
  std::memcpy(out_.data() + position_, c, static_cast<std::size_t>(n));
  position_ = end;
}

void ExrMemoryIStream::Need(int n) const {
  if (n < 0 || position_ > bytes_.size() || bytes_.size() - position_ < static_cast<uint64_t>(n)) {
    throw IEX_NAMESPACE::InputExc("unexpected end of EXR data");
  }
}

bool ExrMemoryIStream::read(char c[], int n) {
  Need(n);
  std::memcpy(c, bytes_.data() + position_, static_cast<std::size_t>(n));
  position_ += static_cast<uint64_t>(n);
  return position_ < bytes_.size();
}

char* ExrMemoryIStream::readMemoryMapped(int n) {
  Need(n);
  // OpenEXR's interface hands out a non-const pointer but only reads through it.
  char* p = const_cast<char*>(bytes_.data() + position_);
  position_ += static_cast<uint64_t>(n);
  return p;
}

std::string EncodeExr(const Imf::Header& header, const Imf::FrameBuffer& frame_buffer,
                      const std::string& what) {
  std::string bytes;
  try {
    ExrStringOStream stream(bytes);
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame_buffer);
    const Imath::Box2i& data = header.dataWindow();
    file.writePixels(data.max.y - data.min.y + 1);
  } catch (const std::exception& e) {
    throw ImageError("cannot encode " + what + ": " + e.what());
  }
  return bytes;
}

}  // namespace farm
