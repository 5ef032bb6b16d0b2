#pragma once
// One property for every message decoder: any input either decodes or yields an error with a
// detail; whatever decodes re-encodes to JSON that decodes to the same message.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "ocp/json_codec.hpp"

namespace ocp::fuzz {

template <class Decode, class Encode>
void check_message(const std::uint8_t* data, std::size_t size, Decode decode, Encode encode) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const auto decoded = decode(input);
  if (!decoded.ok()) {
    if (decoded.error().detail.empty()) __builtin_trap();
    return;
  }
  std::string encoded;
  encode(decoded.value(), encoded);
  if (!validate_raw_json(encoded).ok()) __builtin_trap();
  const auto again = decode(encoded);
  if (!again.ok() || !(again.value() == decoded.value())) __builtin_trap();
}

}  // namespace ocp::fuzz
