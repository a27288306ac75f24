#pragma once
/// @file
/// Incremental SHA-256 (OpenSSL's EVP interface, libcrypto): what output manifests and
/// checkpoints record of their files, computed as the bytes are written or read.

#include <cstddef>
#include <memory>
#include <string>

namespace vpsim {

class Sha256 {
public:
    /// @throw Error when libcrypto cannot make a digest
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;
    void update(const void* data, size_t bytes);
    /// The digest of everything given, 64 lowercase hex digits (once: it ends the digest).
    std::string hex();

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace vpsim
