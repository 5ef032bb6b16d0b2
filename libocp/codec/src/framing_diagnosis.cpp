#include "ocp/framing_diagnosis.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include <fmt/format.h>

namespace ocp {

namespace {

constexpr std::size_t quote_chars = 8;
// Enough for the quote and for recognising a protocol by its first word.
constexpr std::size_t sniff_bytes = 16;

bool starts_with(std::string_view text, std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; }

bool is_text(std::string_view bytes) {
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    if (!std::isprint(byte) && byte != '\r' && byte != '\n' && byte != '\t') return false;
  }
  return true;
}

std::string guess(std::string_view bytes, std::uint32_t length, std::size_t limit) {
  static constexpr std::array<std::string_view, 9> methods{"GET ", "POST ", "PUT ", "HEAD ", "DELETE ",
                                                           "OPTIONS ", "PATCH ", "CONNECT ", "PRI * "};
  for (const auto method : methods) {
    if (starts_with(bytes, method.substr(0, std::min(bytes.size(), method.size())))) return "an HTTP client?";
  }
  if (starts_with(bytes, "HTTP/")) return "an HTTP server?";
  if (starts_with(bytes, "SSH-")) return "an SSH peer?";
  if (bytes.size() >= 2 && bytes[0] == '\x16' && bytes[1] == '\x03') return "a TLS handshake: OCP is plain TCP";
  const auto first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && (bytes[first] == '{' || bytes[first] == '[')) {
    return "JSON without the 4-byte length prefix?";
  }
  if (is_text(bytes)) return "plain text, not a length-prefixed frame";
  return fmt::format("a length prefix of {} bytes, far over the {}-byte limit", length, limit);
}

}  // namespace

std::string quote_first_bytes(std::string_view first_bytes) {
  std::string text;
  for (const char c : first_bytes.substr(0, quote_chars)) {
    text += std::isprint(static_cast<unsigned char>(c)) ? c : '.';
  }
  if (first_bytes.size() > quote_chars) text += "…";
  return text;
}

std::string describe_non_ocp_bytes(std::string_view first_bytes, std::size_t payload_limit_bytes) {
  const std::uint32_t length = read_length_prefix(first_bytes).value_or(0);
  return fmt::format("this does not look like OCP framing (got '{}': {})", quote_first_bytes(first_bytes),
                     guess(first_bytes.substr(0, sniff_bytes), length, payload_limit_bytes));
}

std::optional<std::string> FramingSniffer::observe(std::string_view bytes) {
  if (done_) return std::nullopt;
  first_bytes_.append(bytes.substr(0, sniff_bytes - std::min(sniff_bytes, first_bytes_.size())));
  const auto length = read_length_prefix(first_bytes_);
  if (!length) return std::nullopt;
  done_ = true;
  if (*length < implausible_from_) return std::nullopt;
  diagnosis_ = describe_non_ocp_bytes(first_bytes_);
  return diagnosis_;
}

}  // namespace ocp
