#include "vpsim/core/sha256.h"

#include <openssl/evp.h>

#include "vpsim/core/error.h"

namespace vpsim {

struct Sha256::Impl {
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> context{EVP_MD_CTX_new(), EVP_MD_CTX_free};
};

Sha256::Sha256() : mImpl(std::make_unique<Impl>()) {
    if (!mImpl->context || EVP_DigestInit_ex(mImpl->context.get(), EVP_sha256(), nullptr) != 1)
        throw Error("SHA-256: cannot initialise libcrypto digest");
}

Sha256::~Sha256() = default;

void Sha256::update(const void* data, size_t bytes) {
    if (EVP_DigestUpdate(mImpl->context.get(), data, bytes) != 1)
        throw Error("SHA-256: digest update failed");
}

std::string Sha256::hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(mImpl->context.get(), digest, &length) != 1)
        throw Error("SHA-256: digest final failed");
    static const char* digits = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < length; ++i) {
        out += digits[digest[i] >> 4];
        out += digits[digest[i] & 15];
    }
    return out;
}

}  // namespace vpsim
