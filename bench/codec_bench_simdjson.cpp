// The decode speed limit: simdjson On-Demand doing our decoders' work on the same two messages
// (every field into the typed structs of messages.hpp, keys in any order, user data kept as its
// JSON text, a type error an error). Built when simdjson is installed (bench/CMakeLists.txt).
// Generous to simdjson: the padded copy of the input it needs is made once, outside the loop,
// and it checks less than ours does (no nesting limit, no lone-surrogate or NUL checks).
#include <benchmark/benchmark.h>
#include <simdjson.h>

#include <string>
#include <utility>

#include "codec_bench_messages.hpp"
#include "ocp/messages.hpp"

namespace {

namespace ondemand = simdjson::ondemand;

// Any error (missing field, wrong type, bad JSON) ends the decode, as in ours.
struct DecodeFailed {};

template <class T>
T take(simdjson::simdjson_result<T>&& result) {
  T value{};
  if (std::move(result).get(value) != simdjson::SUCCESS) throw DecodeFailed{};
  return value;
}

void read_buttons(ondemand::object buttons, ocp::Buttons& out) {
  out.a = take(buttons["a"].get_bool());
  out.b = take(buttons["b"].get_bool());
  out.x = take(buttons["x"].get_bool());
  out.y = take(buttons["y"].get_bool());
  out.left_bumper = take(buttons["left_bumper"].get_bool());
  out.right_bumper = take(buttons["right_bumper"].get_bool());
  out.back = take(buttons["back"].get_bool());
  out.start = take(buttons["start"].get_bool());
  out.guide = take(buttons["guide"].get_bool());
  out.left_thumb = take(buttons["left_thumb"].get_bool());
  out.right_thumb = take(buttons["right_thumb"].get_bool());
  out.dpad_up = take(buttons["dpad_up"].get_bool());
  out.dpad_right = take(buttons["dpad_right"].get_bool());
  out.dpad_down = take(buttons["dpad_down"].get_bool());
  out.dpad_left = take(buttons["dpad_left"].get_bool());
}

void read_axes(ondemand::object axes, ocp::Axes& out) {
  out.left_x = take(axes["left_x"].get_double());
  out.left_y = take(axes["left_y"].get_double());
  out.right_x = take(axes["right_x"].get_double());
  out.right_y = take(axes["right_y"].get_double());
  out.left_trigger = take(axes["left_trigger"].get_double());
  out.right_trigger = take(axes["right_trigger"].get_double());
}

ocp::OcpControlMessage decode_control(ondemand::parser& parser, const simdjson::padded_string& text) {
  ondemand::document document;
  if (parser.iterate(text).get(document) != simdjson::SUCCESS) throw DecodeFailed{};
  ondemand::object root = take(document.get_object());
  ocp::OcpControlMessage message;
  ondemand::value controller = take(root["controller"]);
  if (!take(controller.is_null())) {
    ondemand::object object = take(controller.get_object());
    ocp::Controller& out = message.controller.emplace();
    read_buttons(take(object["buttons"].get_object()), out.buttons);
    read_axes(take(object["axes"].get_object()), out.axes);
  }
  ondemand::object telemetry = take(root["telemetry"].get_object());
  message.telemetry.latency_ms = take(telemetry["latency"].get_uint64());
  message.telemetry.fault = take(telemetry["fault"].get_bool());
  message.telemetry.fault_reason = std::string(take(telemetry["fault_reason"].get_string()));
  message.ack.ack_time = take(root["ack_time"].get_uint64());
  message.ack.ack_time_mac = static_cast<std::uint32_t>(take(root["ack_time_mac"].get_uint64()));
  ondemand::value user_data = take(root["client_user_data"]);
  message.client_user_data = ocp::RawJson{std::string(take(take(user_data.get_object()).raw_json()))};
  return message;
}

ocp::VehicleResponseMessage decode_response(ondemand::parser& parser,
                                            const simdjson::padded_string& text) {
  ondemand::document document;
  if (parser.iterate(text).get(document) != simdjson::SUCCESS) throw DecodeFailed{};
  ondemand::object root = take(document.get_object());
  ocp::VehicleResponseMessage message;
  message.ack.ack_time = take(root["ack_time"].get_uint64());
  message.ack.ack_time_mac = static_cast<std::uint32_t>(take(root["ack_time_mac"].get_uint64()));
  ondemand::object data = take(root["vehicle_user_data"].get_object());
  ocp::VehicleUserData& out = message.vehicle_user_data.emplace();
  ondemand::object pos = take(data["pos"].get_object());
  out.pos = ocp::Position{take(pos["lat"].get_double()), take(pos["lon"].get_double())};
  out.user_data.text = std::string(take(take(data["user_data"].get_object()).raw_json()));
  return message;
}

void BM_ControlDecode_Simdjson(benchmark::State& state) {
  const simdjson::padded_string text(std::string(ocp::bench::control_text));
  ondemand::parser parser;
  for (auto _ : state) {
    auto message = decode_control(parser, text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ControlDecode_Simdjson);

void BM_ResponseDecode_Simdjson(benchmark::State& state) {
  const simdjson::padded_string text(std::string(ocp::bench::response_text));
  ondemand::parser parser;
  for (auto _ : state) {
    auto message = decode_response(parser, text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ResponseDecode_Simdjson);

// Which implementation this file's On-Demand code was compiled for (haswell, fallback...):
// the header's, not the shared library's builtin_implementation().
const bool implementation_noted = [] {
  benchmark::AddCustomContext("simdjson On-Demand", SIMDJSON_STRINGIFY(SIMDJSON_BUILTIN_IMPLEMENTATION));
  return true;
}();

}  // namespace
