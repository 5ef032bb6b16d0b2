// libFuzzer target: decode_control_message on arbitrary bytes (see fuzz_message.hpp for the property).
#include "fuzz_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ocp::fuzz::check_message(
      data, size, [](std::string_view json) { return ocp::decode_control_message(json); },
      [](const auto& message, std::string& out) { ocp::encode_control_message(message, out); });
  return 0;
}
