#pragma once
// ack_time_mac (SPEC §5): first 4 bytes, read as little-endian u32, of
// HMAC-SHA256(key, ack_time as 8 little-endian bytes). The key's pad blocks are hashed once
// per AckMac; a call copies those states and hashes 8 + 32 bytes, allocating nothing.
#include <array>
#include <cstdint>
#include <memory>

namespace ocp {

using MacKey = std::array<std::uint8_t, 32>;

// 32 bytes from OpenSSL's CSPRNG. Aborts only if the CSPRNG itself fails (it never should).
MacKey random_mac_key();

class AckMac {
 public:
  explicit AckMac(const MacKey& key);
  ~AckMac();
  AckMac(AckMac&&) noexcept;
  AckMac& operator=(AckMac&&) noexcept;
  AckMac(const AckMac&) = delete;
  AckMac& operator=(const AckMac&) = delete;

  std::uint32_t compute(std::uint64_t ack_time);
  // Constant-time comparison of the expected MAC with the returned one.
  bool verify(std::uint64_t ack_time, std::uint32_t ack_time_mac);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ocp
