// libFuzzer target: decode_control_message on arbitrary bytes (see fuzz_message.hpp for the
// property), and the vehicle client's pair scan against it: whenever both find a pair, the same.
#include "fuzz_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ocp::fuzz::check_message(
      data, size, [](std::string_view json) { return ocp::decode_control_message(json); },
      [](const auto& message, std::string& out) { ocp::encode_control_message(message, out); });
  const std::string_view json(reinterpret_cast<const char*>(data), size);
  const auto scanned = ocp::scan_control_ack_pair(json);
  const auto decoded = ocp::decode_control_message(json);
  if (scanned && decoded.ok() && !(*scanned == decoded.value().ack)) __builtin_trap();
  return 0;
}
