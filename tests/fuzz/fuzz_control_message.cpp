// libFuzzer target: decode_control_message on arbitrary bytes (see fuzz_message.hpp for the
// property), and its two-step form (ControlMessageDecoder, the vehicle client's echo path)
// against it: the same result, and the early pair equal to the decoded one whenever both exist.
#include "fuzz_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ocp::fuzz::check_message(
      data, size, [](std::string_view json) { return ocp::decode_control_message(json); },
      [](const auto& message, std::string& out) { ocp::encode_control_message(message, out); });
  const std::string_view json(reinterpret_cast<const char*>(data), size);
  const auto decoded = ocp::decode_control_message(json);
  ocp::ControlMessageDecoder two_step;
  const auto pair = two_step.start(json);
  const auto finished = two_step.finish();
  if (finished.ok() != decoded.ok()) __builtin_trap();
  if (decoded.ok() && !(finished.value() == decoded.value())) __builtin_trap();
  if (!decoded.ok() && finished.error().message() != decoded.error().message()) __builtin_trap();
  if (pair && decoded.ok() && !(*pair == decoded.value().ack)) __builtin_trap();
  return 0;
}
