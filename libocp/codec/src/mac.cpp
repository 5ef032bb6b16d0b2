#include "ocp/mac.hpp"

// The low-level SHA-256 functions are deprecated in OpenSSL 3.0; see AckMac::State for why we
// use them anyway.
#define OPENSSL_SUPPRESS_DEPRECATED
#include <openssl/crypto.h>
#include <openssl/rand.h>
#include <openssl/sha.h>

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

// HMAC-SHA256 (RFC 2104) with the key's inner and outer pad blocks hashed once at
// construction. Per call: two copies of a plain SHA-256 state, two short updates, two finals.
// Why OpenSSL's low-level SHA256_* functions (deprecated in 3.0, still built and maintained):
// their state is a plain struct, so copying the precomputed state is a memcpy. The EVP path
// (EVP_MD_CTX_copy_ex) allocates and frees a provider context per copy in OpenSSL 3.0 — two
// allocations per MAC — and a reused EVP_MAC_CTX re-dispatches through the provider on every
// init; at 10 000 vehicles (two MACs per vehicle per 10 ms tick) that was ~9 % of a fleet run.
// Both paths use the same (SHA-NI when present) block function. Same bytes out; the tests
// cross-check against EVP_MAC and the OpenSSL CLI.
struct AckMac::State {
  SHA256_CTX inner{};  // SHA-256 state after (key ^ ipad)
  SHA256_CTX outer{};  // SHA-256 state after (key ^ opad)

  ~State() {
    OPENSSL_cleanse(&inner, sizeof inner);
    OPENSSL_cleanse(&outer, sizeof outer);
  }
};

AckMac::AckMac(const MacKey& key) : state_(std::make_unique<State>()) {
  static_assert(std::tuple_size_v<MacKey> <= sha256_block_bytes, "a longer key would be hashed first");
  State& state = *state_;
  unsigned char inner_pad[sha256_block_bytes];
  unsigned char outer_pad[sha256_block_bytes];
  for (std::size_t i = 0; i < sha256_block_bytes; ++i) {
    const unsigned char key_byte = i < key.size() ? key[i] : 0;
    inner_pad[i] = key_byte ^ 0x36;
    outer_pad[i] = key_byte ^ 0x5c;
  }
  if (SHA256_Init(&state.inner) != 1 || SHA256_Update(&state.inner, inner_pad, sizeof inner_pad) != 1 ||
      SHA256_Init(&state.outer) != 1 || SHA256_Update(&state.outer, outer_pad, sizeof outer_pad) != 1) {
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
  const State& state = *state_;
  unsigned char inner_hash[sha256_digest_bytes];
  unsigned char mac[sha256_digest_bytes];
  SHA256_CTX work = state.inner;
  if (SHA256_Update(&work, message, sizeof message) != 1 || SHA256_Final(inner_hash, &work) != 1) {
    fail("HMAC-SHA256 inner hash");
  }
  work = state.outer;
  if (SHA256_Update(&work, inner_hash, sizeof inner_hash) != 1 || SHA256_Final(mac, &work) != 1) {
    fail("HMAC-SHA256 outer hash");
  }
  return static_cast<std::uint32_t>(mac[0]) | static_cast<std::uint32_t>(mac[1]) << 8 |
         static_cast<std::uint32_t>(mac[2]) << 16 | static_cast<std::uint32_t>(mac[3]) << 24;
}

bool AckMac::verify(std::uint64_t ack_time, std::uint32_t ack_time_mac) {
  const std::uint32_t expected = compute(ack_time);
  return CRYPTO_memcmp(&expected, &ack_time_mac, sizeof expected) == 0;
}

}  // namespace ocp
