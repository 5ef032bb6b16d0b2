#include "ocp/mac.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <cstdio>
#include <cstdlib>

namespace ocp {
namespace {

constexpr std::size_t sha256_block_bytes = 64;
constexpr std::size_t sha256_digest_bytes = 32;

[[noreturn]] void fail(const char* what) {
  // Only reachable if OpenSSL itself is broken (no SHA-256 provider, CSPRNG failure).
  std::fprintf(stderr, "fatal: OpenSSL %s failed\n", what);
  std::abort();
}

}  // namespace

MacKey random_mac_key() {
  MacKey key{};
  if (RAND_bytes(key.data(), static_cast<int>(key.size())) != 1) {
    fail("RAND_bytes");
  }
  return key;
}

// HMAC-SHA256 (RFC 2104) on OpenSSL 3's EVP digest API, with the key's inner and outer pad
// blocks hashed once at construction. Per call: two context copies, two short updates, two
// finals. Measured here this costs ~150 ns against ~350 ns for a reused EVP_MAC_CTX
// (EVP_MAC_init with a null key, then update/final): the EVP_MAC path re-dispatches through
// the provider and re-checks parameters on every init. Same bytes out; the tests cross-check
// against EVP_MAC and the OpenSSL CLI.
struct AckMac::State {
  EVP_MD* digest = nullptr;
  EVP_MD_CTX* inner = nullptr;  // SHA-256 state after (key ^ ipad)
  EVP_MD_CTX* outer = nullptr;  // SHA-256 state after (key ^ opad)
  EVP_MD_CTX* work = nullptr;

  ~State() {
    EVP_MD_CTX_free(work);
    EVP_MD_CTX_free(outer);
    EVP_MD_CTX_free(inner);
    EVP_MD_free(digest);
  }
};

AckMac::AckMac(const MacKey& key) : state_(std::make_unique<State>()) {
  static_assert(std::tuple_size_v<MacKey> <= sha256_block_bytes, "a longer key would be hashed first");
  State& state = *state_;
  state.digest = EVP_MD_fetch(nullptr, "SHA256", nullptr);
  state.inner = EVP_MD_CTX_new();
  state.outer = EVP_MD_CTX_new();
  state.work = EVP_MD_CTX_new();
  if (state.digest == nullptr || state.inner == nullptr || state.outer == nullptr || state.work == nullptr) {
    fail("SHA-256 setup");
  }
  unsigned char inner_pad[sha256_block_bytes];
  unsigned char outer_pad[sha256_block_bytes];
  for (std::size_t i = 0; i < sha256_block_bytes; ++i) {
    const unsigned char key_byte = i < key.size() ? key[i] : 0;
    inner_pad[i] = key_byte ^ 0x36;
    outer_pad[i] = key_byte ^ 0x5c;
  }
  if (EVP_DigestInit_ex(state.inner, state.digest, nullptr) != 1 ||
      EVP_DigestUpdate(state.inner, inner_pad, sizeof inner_pad) != 1 ||
      EVP_DigestInit_ex(state.outer, state.digest, nullptr) != 1 ||
      EVP_DigestUpdate(state.outer, outer_pad, sizeof outer_pad) != 1) {
    fail("HMAC key setup");
  }
  OPENSSL_cleanse(inner_pad, sizeof inner_pad);
  OPENSSL_cleanse(outer_pad, sizeof outer_pad);
}

AckMac::~AckMac() = default;
AckMac::AckMac(AckMac&&) noexcept = default;
AckMac& AckMac::operator=(AckMac&&) noexcept = default;

std::uint32_t AckMac::compute(std::uint64_t ack_time) {
  unsigned char message[8];
  for (std::size_t i = 0; i < sizeof message; ++i) {
    message[i] = static_cast<unsigned char>(ack_time >> (8 * i));
  }
  State& state = *state_;
  unsigned char inner_hash[EVP_MAX_MD_SIZE];
  unsigned char mac[EVP_MAX_MD_SIZE];
  unsigned int inner_size = 0;
  unsigned int mac_size = 0;
  if (EVP_MD_CTX_copy_ex(state.work, state.inner) != 1 ||
      EVP_DigestUpdate(state.work, message, sizeof message) != 1 ||
      EVP_DigestFinal_ex(state.work, inner_hash, &inner_size) != 1 || inner_size != sha256_digest_bytes ||
      EVP_MD_CTX_copy_ex(state.work, state.outer) != 1 ||
      EVP_DigestUpdate(state.work, inner_hash, inner_size) != 1 ||
      EVP_DigestFinal_ex(state.work, mac, &mac_size) != 1 || mac_size != sha256_digest_bytes) {
    fail("HMAC-SHA256");
  }
  return static_cast<std::uint32_t>(mac[0]) | static_cast<std::uint32_t>(mac[1]) << 8 |
         static_cast<std::uint32_t>(mac[2]) << 16 | static_cast<std::uint32_t>(mac[3]) << 24;
}

bool AckMac::verify(std::uint64_t ack_time, std::uint32_t ack_time_mac) {
  const std::uint32_t expected = compute(ack_time);
  return CRYPTO_memcmp(&expected, &ack_time_mac, sizeof expected) == 0;
}

}  // namespace ocp
