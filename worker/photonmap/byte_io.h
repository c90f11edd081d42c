#pragma once

// Little-endian loads and stores for the photon formats. memcpy keeps them free of
// alignment and aliasing assumptions; compilers turn them into single moves.

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

namespace farm::byte_io {

static_assert(std::endian::native == std::endian::little,
              "photon formats are little-endian; add byte swaps for this target");

template <typename T>
T Load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <typename T>
T Load(const char* p) {
  return Load<T>(reinterpret_cast<const unsigned char*>(p));
}

template <typename T>
void Append(std::string& out, T v) {
  char buf[sizeof v];
  std::memcpy(buf, &v, sizeof v);
  out.append(buf, sizeof v);
}

}  // namespace farm::byte_io
