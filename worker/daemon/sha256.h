#pragma once

// Content digests as the blob store names blobs: "sha256:" and 64 lowercase hex digits
// (contract/digest.h checks one).

#include <memory>
#include <string>
#include <string_view>

namespace farm {

// Incremental SHA-256 (OpenSSL's libcrypto), for blobs that arrive in chunks.
class Sha256 {
 public:
  Sha256();
  Sha256(Sha256&&) noexcept;
  Sha256& operator=(Sha256&&) noexcept;
  ~Sha256();

  void Update(std::string_view bytes);
  // The digest of everything passed to Update, as "sha256:<hex>". Call once.
  std::string Finish();

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

// The digest of `bytes`, as "sha256:<hex>".
std::string Sha256Digest(std::string_view bytes);

}  // namespace farm
