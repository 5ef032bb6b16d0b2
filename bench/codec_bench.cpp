// Codec micro benchmarks: our codec against nlohmann::json doing the same work (parse into the
// typed structs, build and serialize), plus the ack MAC; simdjson's decode, the speed limit, is
// in codec_bench_simdjson.cpp and the closing table of ratios in codec_bench_main.cpp.
// Results: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>
#include <string>

#include "ocp/json_codec.hpp"
#include "ocp/mac.hpp"
#include "codec_bench_messages.hpp"

namespace {

using nlohmann::json;
using ocp::bench::control_text;
using ocp::bench::response_text;

// ---- nlohmann baseline: the same typed decode and encode ----

ocp::Controller nlohmann_controller(const json& value) {
  ocp::Controller controller;
  const json& b = value.at("buttons");
  ocp::Buttons& buttons = controller.buttons;
  buttons.a = b.at("a").get<bool>();
  buttons.b = b.at("b").get<bool>();
  buttons.x = b.at("x").get<bool>();
  buttons.y = b.at("y").get<bool>();
  buttons.left_bumper = b.at("left_bumper").get<bool>();
  buttons.right_bumper = b.at("right_bumper").get<bool>();
  buttons.back = b.at("back").get<bool>();
  buttons.start = b.at("start").get<bool>();
  buttons.guide = b.at("guide").get<bool>();
  buttons.left_thumb = b.at("left_thumb").get<bool>();
  buttons.right_thumb = b.at("right_thumb").get<bool>();
  buttons.dpad_up = b.at("dpad_up").get<bool>();
  buttons.dpad_right = b.at("dpad_right").get<bool>();
  buttons.dpad_down = b.at("dpad_down").get<bool>();
  buttons.dpad_left = b.at("dpad_left").get<bool>();
  const json& a = value.at("axes");
  ocp::Axes& axes = controller.axes;
  axes.left_x = a.at("left_x").get<double>();
  axes.left_y = a.at("left_y").get<double>();
  axes.right_x = a.at("right_x").get<double>();
  axes.right_y = a.at("right_y").get<double>();
  axes.left_trigger = a.at("left_trigger").get<double>();
  axes.right_trigger = a.at("right_trigger").get<double>();
  return controller;
}

ocp::OcpControlMessage nlohmann_decode_control(const std::string& text) {
  const json document = json::parse(text);
  ocp::OcpControlMessage message;
  if (const auto it = document.find("controller"); it != document.end() && !it->is_null()) {
    message.controller = nlohmann_controller(*it);
  }
  const json& telemetry = document.at("telemetry");
  message.telemetry.latency_ms = telemetry.at("latency").get<std::uint64_t>();
  message.telemetry.fault = telemetry.at("fault").get<bool>();
  message.telemetry.fault_reason = telemetry.at("fault_reason").get<std::string>();
  if (const auto it = telemetry.find("missing_cameras"); it != telemetry.end()) {
    message.telemetry.missing_cameras = it->get<std::vector<std::string>>();
  }
  message.ack.ack_time = document.at("ack_time").get<std::uint64_t>();
  message.ack.ack_time_mac = document.at("ack_time_mac").get<std::uint32_t>();
  if (const auto it = document.find("client_user_data"); it != document.end() && !it->is_null()) {
    message.client_user_data = ocp::RawJson{it->dump()};
  }
  return message;
}

json nlohmann_controller_json(const ocp::Controller& controller) {
  const ocp::Buttons& b = controller.buttons;
  const ocp::Axes& a = controller.axes;
  return json{{"buttons",
               {{"a", b.a},
                {"b", b.b},
                {"x", b.x},
                {"y", b.y},
                {"left_bumper", b.left_bumper},
                {"right_bumper", b.right_bumper},
                {"back", b.back},
                {"start", b.start},
                {"guide", b.guide},
                {"left_thumb", b.left_thumb},
                {"right_thumb", b.right_thumb},
                {"dpad_up", b.dpad_up},
                {"dpad_right", b.dpad_right},
                {"dpad_down", b.dpad_down},
                {"dpad_left", b.dpad_left}}},
              {"axes",
               {{"left_x", a.left_x},
                {"left_y", a.left_y},
                {"right_x", a.right_x},
                {"right_y", a.right_y},
                {"left_trigger", a.left_trigger},
                {"right_trigger", a.right_trigger}}}};
}

std::string nlohmann_encode_control(const ocp::OcpControlMessage& message) {
  json document;
  document["controller"] =
      message.controller ? nlohmann_controller_json(*message.controller) : json(nullptr);
  document["telemetry"] = {{"latency", message.telemetry.latency_ms},
                           {"fault", message.telemetry.fault},
                           {"fault_reason", message.telemetry.fault_reason},
                           {"missing_cameras", message.telemetry.missing_cameras}};
  document["ack_time"] = message.ack.ack_time;
  document["ack_time_mac"] = message.ack.ack_time_mac;
  if (message.client_user_data) {
    document["client_user_data"] = json::parse(message.client_user_data->text);
  }
  return document.dump();
}

ocp::VehicleResponseMessage nlohmann_decode_response(const std::string& text) {
  const json document = json::parse(text);
  ocp::VehicleResponseMessage message;
  message.ack.ack_time = document.at("ack_time").get<std::uint64_t>();
  message.ack.ack_time_mac = document.at("ack_time_mac").get<std::uint32_t>();
  if (const auto it = document.find("vehicle_user_data"); it != document.end() && !it->is_null()) {
    ocp::VehicleUserData& data = message.vehicle_user_data.emplace();
    if (const auto pos = it->find("pos"); pos != it->end() && !pos->is_null()) {
      data.pos = ocp::Position{pos->at("lat").get<double>(), pos->at("lon").get<double>()};
    }
    data.user_data.text = it->at("user_data").dump();
  }
  return message;
}

std::string nlohmann_encode_response(const ocp::VehicleResponseMessage& message) {
  json document;
  document["ack_time"] = message.ack.ack_time;
  document["ack_time_mac"] = message.ack.ack_time_mac;
  if (message.vehicle_user_data) {
    const ocp::VehicleUserData& data = *message.vehicle_user_data;
    json user_data;
    user_data["pos"] =
        data.pos ? json{{"lat", data.pos->lat}, {"lon", data.pos->lon}} : json(nullptr);
    user_data["user_data"] = json::parse(data.user_data.text);
    document["vehicle_user_data"] = std::move(user_data);
  }
  return document.dump();
}

// ---- our codec ----

void BM_ControlDecode_Ours(benchmark::State& state) {
  const std::string text = control_text;
  for (auto _ : state) {
    auto message = ocp::decode_control_message(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ControlDecode_Ours);

void BM_ControlEncode_Ours(benchmark::State& state) {
  const ocp::OcpControlMessage message = ocp::decode_control_message(control_text).value();
  std::string out;
  for (auto _ : state) {
    ocp::encode_control_message(message, out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ControlEncode_Ours);

void BM_ControlDecodeEncode_Ours(benchmark::State& state) {
  const std::string text = control_text;
  std::string out;
  for (auto _ : state) {
    auto message = ocp::decode_control_message(text);
    ocp::encode_control_message(message.value(), out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ControlDecodeEncode_Ours);

// What the wire carries: the encoder's compact output (the world's steady state takes the
// tokenizer's fast path: all ASCII, no escapes, no exponents).
void BM_ControlDecodeCompact_Ours(benchmark::State& state) {
  std::string text;
  ocp::encode_control_message(ocp::decode_control_message(control_text).value(), text);
  for (auto _ : state) {
    auto message = ocp::decode_control_message(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ControlDecodeCompact_Ours);

// The vehicle client's echo path: the pair after tokenizing, then the rest of the same tokens.
void BM_ControlTwoStepDecodeCompact_Ours(benchmark::State& state) {
  std::string text;
  ocp::encode_control_message(ocp::decode_control_message(control_text).value(), text);
  ocp::ControlMessageDecoder decoder;
  for (auto _ : state) {
    auto pair = decoder.start(text);
    benchmark::DoNotOptimize(pair);
    auto message = decoder.finish();
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ControlTwoStepDecodeCompact_Ours);

// The same with one non-ASCII string: falls back to RapidJSON with UTF-8 validation.
void BM_ControlDecodeCompactNonAscii_Ours(benchmark::State& state) {
  ocp::OcpControlMessage message = ocp::decode_control_message(control_text).value();
  message.telemetry.fault_reason = "Kamera bak: fel på länk";
  std::string text;
  ocp::encode_control_message(message, text);
  for (auto _ : state) {
    auto decoded = ocp::decode_control_message(text);
    benchmark::DoNotOptimize(decoded);
  }
}
BENCHMARK(BM_ControlDecodeCompactNonAscii_Ours);

void BM_ResponseDecode_Ours(benchmark::State& state) {
  const std::string text = response_text;
  for (auto _ : state) {
    auto message = ocp::decode_vehicle_response(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ResponseDecode_Ours);

void BM_ResponseDecodeCompact_Ours(benchmark::State& state) {
  std::string text;
  ocp::encode_vehicle_response(ocp::decode_vehicle_response(response_text).value(), text);
  for (auto _ : state) {
    auto message = ocp::decode_vehicle_response(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ResponseDecodeCompact_Ours);

void BM_ResponseEncode_Ours(benchmark::State& state) {
  const ocp::VehicleResponseMessage message = ocp::decode_vehicle_response(response_text).value();
  std::string out;
  for (auto _ : state) {
    ocp::encode_vehicle_response(message, out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ResponseEncode_Ours);

void BM_ResponseDecodeEncode_Ours(benchmark::State& state) {
  const std::string text = response_text;
  std::string out;
  for (auto _ : state) {
    auto message = ocp::decode_vehicle_response(text);
    ocp::encode_vehicle_response(message.value(), out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ResponseDecodeEncode_Ours);

// ---- nlohmann baseline ----

void BM_ControlDecode_Nlohmann(benchmark::State& state) {
  const std::string text = control_text;
  for (auto _ : state) {
    auto message = nlohmann_decode_control(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ControlDecode_Nlohmann);

void BM_ControlEncode_Nlohmann(benchmark::State& state) {
  const ocp::OcpControlMessage message = nlohmann_decode_control(control_text);
  for (auto _ : state) {
    std::string out = nlohmann_encode_control(message);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ControlEncode_Nlohmann);

void BM_ControlDecodeEncode_Nlohmann(benchmark::State& state) {
  const std::string text = control_text;
  for (auto _ : state) {
    std::string out = nlohmann_encode_control(nlohmann_decode_control(text));
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ControlDecodeEncode_Nlohmann);

void BM_ResponseDecode_Nlohmann(benchmark::State& state) {
  const std::string text = response_text;
  for (auto _ : state) {
    auto message = nlohmann_decode_response(text);
    benchmark::DoNotOptimize(message);
  }
}
BENCHMARK(BM_ResponseDecode_Nlohmann);

void BM_ResponseEncode_Nlohmann(benchmark::State& state) {
  const ocp::VehicleResponseMessage message = nlohmann_decode_response(response_text);
  for (auto _ : state) {
    std::string out = nlohmann_encode_response(message);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ResponseEncode_Nlohmann);

void BM_ResponseDecodeEncode_Nlohmann(benchmark::State& state) {
  const std::string text = response_text;
  for (auto _ : state) {
    std::string out = nlohmann_encode_response(nlohmann_decode_response(text));
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ResponseDecodeEncode_Nlohmann);

// ---- ack MAC (SPEC §5) ----

void BM_MacIssue(benchmark::State& state) {
  ocp::AckMac mac(ocp::random_mac_key());
  std::uint64_t ack_time = 9007199254740993u;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mac.compute(ack_time++));
  }
}
BENCHMARK(BM_MacIssue);

void BM_MacVerify(benchmark::State& state) {
  ocp::AckMac mac(ocp::random_mac_key());
  const std::uint64_t ack_time = 9007199254740993u;
  const std::uint32_t tag = mac.compute(ack_time);
  for (auto _ : state) {
    benchmark::DoNotOptimize(mac.verify(ack_time, tag));
  }
}
BENCHMARK(BM_MacVerify);

void BM_MacIssueAndVerify(benchmark::State& state) {
  ocp::AckMac mac(ocp::random_mac_key());
  std::uint64_t ack_time = 9007199254740993u;
  for (auto _ : state) {
    const std::uint32_t tag = mac.compute(ack_time);
    benchmark::DoNotOptimize(mac.verify(ack_time, tag));
    ++ack_time;
  }
}
BENCHMARK(BM_MacIssueAndVerify);

}  // namespace
