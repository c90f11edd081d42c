#pragma once

// A content digest as the contract spells one (FieldRule.digest, blob names): "sha256:"
// and exactly 64 lowercase hex digits. Header-only, so that code without the protocol
// library (the daemon's cache) checks digests the same way. Digests come from the network
// and name files in the cache, so nothing else may pass.

#include <algorithm>
#include <string_view>

namespace farm::contract {

inline constexpr std::string_view kDigestPrefix = "sha256:";

inline bool IsDigest(std::string_view s) {
  if (s.size() != kDigestPrefix.size() + 64 || !s.starts_with(kDigestPrefix)) return false;
  return std::all_of(s.begin() + kDigestPrefix.size(), s.end(),
                     [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

}  // namespace farm::contract
