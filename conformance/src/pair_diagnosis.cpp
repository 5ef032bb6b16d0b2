#include "conformance/pair_diagnosis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace ocp::conformance {
namespace {

constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;
constexpr std::uint64_t double_spacing_near_2_to_64 = std::uint64_t{1} << 11;

std::uint64_t distance(std::uint64_t a, std::uint64_t b) { return a > b ? a - b : b - a; }

const AckPair* rounded_from(const AckPair& altered, const std::vector<AckPair>& sent) {
  for (const AckPair& original : sent) {
    if (original.ack_time_mac == altered.ack_time_mac && original.ack_time >= two_to_53 &&
        original.ack_time != altered.ack_time && distance(original.ack_time, altered.ack_time) < double_spacing_near_2_to_64) {
      return &original;
    }
  }
  return nullptr;
}

bool sent_ack_time(std::uint64_t ack_time, const std::vector<AckPair>& sent) {
  return std::any_of(sent.begin(), sent.end(), [&](const AckPair& p) { return p.ack_time == ack_time; });
}

bool sent_mac(std::uint32_t mac, const std::vector<AckPair>& sent) {
  return std::any_of(sent.begin(), sent.end(), [&](const AckPair& p) { return p.ack_time_mac == mac; });
}

}  // namespace

PairDiagnosis diagnose_altered_pairs(const std::vector<AckPair>& altered, const std::vector<AckPair>& sent) {
  for (const AckPair& pair : altered) {
    if (const AckPair* original = rounded_from(pair, sent)) {
      return {"ack_time rounded through a double: parse it as an unsigned 64-bit integer and copy it byte for byte",
              fmt::format("{} came back as {} (off by {})", original->ack_time, pair.ack_time,
                          distance(original->ack_time, pair.ack_time))};
    }
  }
  for (const AckPair& pair : altered) {
    if (sent_ack_time(pair.ack_time, sent) && sent_mac(pair.ack_time_mac, sent)) {
      return {"a partial echo: ack_time and ack_time_mac taken from different control messages; echo both fields of the "
              "same (latest) message",
              fmt::format("ack_time {} with ack_time_mac {}", pair.ack_time, pair.ack_time_mac)};
    }
  }
  for (const AckPair& pair : altered) {
    if (sent_ack_time(pair.ack_time, sent)) {
      return {"ack_time_mac altered: copy it unchanged (an unsigned 32-bit integer)",
              fmt::format("ack_time {} was sent, but never with ack_time_mac {}", pair.ack_time, pair.ack_time_mac)};
    }
  }
  return {};
}

}  // namespace ocp::conformance
