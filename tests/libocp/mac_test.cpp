#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "ocp/mac.hpp"

namespace ocp {
namespace {

// Key 00 01 02 … 1f. Expected values produced independently with the OpenSSL CLI:
//   KEY=000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f
//   python3 -c "import sys; sys.stdout.buffer.write((ACK_TIME).to_bytes(8, 'little'))" |
//     openssl dgst -sha256 -mac HMAC -macopt hexkey:$KEY
// and taking the first 4 digest bytes as a little-endian u32 (e.g. digest 9f0cd9b9… →
// 0xb9d90c9f). Cross-checked with Python's hmac module.
MacKey test_key() {
  MacKey key{};
  for (std::size_t i = 0; i < key.size(); ++i) {
    key[i] = static_cast<std::uint8_t>(i);
  }
  return key;
}

TEST(AckMac, MatchesIndependentlyComputedVectors) {
  AckMac mac(test_key());
  EXPECT_EQ(mac.compute(0), 0xb9d90c9fu);
  EXPECT_EQ(mac.compute(1), 0x4e5d343bu);
  EXPECT_EQ(mac.compute(0x0123456789abcdefULL), 0xfe34878cu);
  EXPECT_EQ(mac.compute(9007199254740993ULL), 0xda58368cu);  // 2^53 + 1
  EXPECT_EQ(mac.compute(std::numeric_limits<std::uint64_t>::max()), 0x3e79e151u);
}

TEST(AckMac, RepeatedCallsGiveTheSameResult) {
  AckMac mac(test_key());
  const std::uint32_t first = mac.compute(42);
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(mac.compute(42), first);
  }
}

TEST(AckMac, VerifyAcceptsTheIssuedMac) {
  AckMac mac(test_key());
  const std::uint64_t ack_time = std::numeric_limits<std::uint64_t>::max();
  EXPECT_TRUE(mac.verify(ack_time, mac.compute(ack_time)));
  EXPECT_TRUE(mac.verify(0, 0xb9d90c9fu));
}

TEST(AckMac, VerifyRejectsAnyFlippedBitInTheMac) {
  AckMac mac(test_key());
  const std::uint32_t good = mac.compute(123456789);
  for (int bit = 0; bit < 32; ++bit) {
    EXPECT_FALSE(mac.verify(123456789, good ^ (1u << bit))) << "bit " << bit;
  }
}

TEST(AckMac, VerifyRejectsAnyFlippedBitInTheAckTime) {
  AckMac mac(test_key());
  const std::uint64_t ack_time = 9007199254740993ULL;
  const std::uint32_t good = mac.compute(ack_time);
  for (int bit = 0; bit < 64; ++bit) {
    EXPECT_FALSE(mac.verify(ack_time ^ (std::uint64_t{1} << bit), good)) << "bit " << bit;
  }
}

TEST(AckMac, DifferentKeysGiveDifferentMacs) {
  MacKey other = test_key();
  other[31] ^= 1;
  AckMac mac(test_key());
  AckMac other_mac(other);
  EXPECT_NE(mac.compute(1), other_mac.compute(1));
  EXPECT_FALSE(other_mac.verify(1, mac.compute(1)));
}

TEST(AckMac, RandomKeysDiffer) {
  const MacKey first = random_mac_key();
  const MacKey second = random_mac_key();
  EXPECT_NE(first, second);
  EXPECT_NE(first, MacKey{});
}

TEST(AckMac, MovedMacKeepsItsKey) {
  AckMac original(test_key());
  AckMac moved(std::move(original));
  EXPECT_EQ(moved.compute(1), 0x4e5d343bu);
  AckMac assigned(random_mac_key());
  assigned = std::move(moved);
  EXPECT_EQ(assigned.compute(0), 0xb9d90c9fu);
}

}  // namespace
}  // namespace ocp

#include <openssl/evp.h>

namespace ocp {
namespace {

// The same value from OpenSSL's own HMAC (EVP_Q_mac), for many ack times and one random key.
std::uint32_t reference_mac(const MacKey& key, std::uint64_t ack_time) {
  unsigned char message[8];
  for (int i = 0; i < 8; ++i) {
    message[i] = static_cast<unsigned char>(ack_time >> (8 * i));
  }
  unsigned char digest[32];
  std::size_t digest_size = 0;
  char sha256[] = "SHA256";
  EVP_Q_mac(nullptr, "HMAC", nullptr, sha256, nullptr, key.data(), key.size(), message, sizeof message, digest,
            sizeof digest, &digest_size);
  return static_cast<std::uint32_t>(digest[0]) | static_cast<std::uint32_t>(digest[1]) << 8 |
         static_cast<std::uint32_t>(digest[2]) << 16 | static_cast<std::uint32_t>(digest[3]) << 24;
}

TEST(AckMac, AgreesWithOpenSslHmacForManyAckTimes) {
  const MacKey key = random_mac_key();
  AckMac mac(key);
  std::uint64_t ack_time = 0x9e3779b97f4a7c15ULL;
  for (int i = 0; i < 200; ++i) {
    ack_time = ack_time * 6364136223846793005ULL + 1442695040888963407ULL;
    ASSERT_EQ(mac.compute(ack_time), reference_mac(key, ack_time)) << ack_time;
  }
}

}  // namespace
}  // namespace ocp
