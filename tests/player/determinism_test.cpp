// Same inputs → the same output sequence, byte for byte, in virtual time.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

// Runs a busy two-vehicle world for 3 s and returns every output as text.
std::vector<std::string> run_once() {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  harness.pong_delay = Micros{23'456};
  EXPECT_TRUE(harness.add_vehicle("truck-1").ok());
  EXPECT_TRUE(harness.add_vehicle("truck-2").ok());
  Waveform waveform;
  waveform.waves.push_back(SineWave{GamepadAxis::left_x, 0.8, Micros{700'000}, 0.3});
  waveform.waves.push_back(SineWave{GamepadAxis::right_trigger, 0.5, Micros{1'300'000}, 0.0});
  harness.player.gamepad().set_waveform(waveform);
  harness.player.start();

  std::vector<std::string> outputs;
  TestOperatorClient client(harness);
  for (std::int64_t ms = 0; ms < 3000; ms += 33) {
    harness.video_at(at_ms(ms) + Micros{41'000}, "truck-1",
                     AckPair{static_cast<std::uint64_t>(ms) * 1000 + (1ULL << 60), static_cast<std::uint32_t>(ms * 7919)});
    StreamerFeedback feedback;
    feedback.latency_ms = static_cast<std::uint64_t>(40 + ms % 17);
    harness.deliver_at(at_ms(ms) + Micros{40'000}, ms % 2 ? "truck-1" : "truck-2", LinkMessage{feedback});
  }
  harness.executor.call_at(at_ms(250), [&] {
    ClientVehicleEntry entry;
    entry.user_data = RawJson{R"({"seq":1})"};
    entry.ack_time_returned = 77;
    entry.ack_time_mac_returned = 88;
    client.send(client_entry("truck-1", entry, "truck-1"));
  });
  harness.executor.call_at(at_ms(1200), [&] { harness.player.gamepad().unplug(); });
  harness.executor.call_at(at_ms(1700), [&] { harness.player.gamepad().replug(); });
  harness.run_until(at_ms(3000));

  for (const auto& [name, items] : harness.sent) {
    for (const Sent& item : items) {
      std::string text = fmt::format("{} {} {}", name, item.time.count(), item.message.index());
      if (const auto* control = std::get_if<OperatorControl>(&item.message)) {
        std::string controller = "null";
        if (control->controller) encode_controller(*control->controller, controller);
        text += fmt::format(" seq={} ctl={} ud={} ack={}", control->sequence, controller,
                            control->client_user_data ? control->client_user_data->text : "-",
                            control->returned_ack ? control->returned_ack->ack_time : 0);
        for (FaultId fault : control->sender_faults) text += fmt::format(" {}", fault_identifier(fault));
      }
      outputs.push_back(std::move(text));
    }
  }
  for (const VehicleOcpShared& shared : client.received) {
    std::string json;
    encode_vehicle_ocp_shared(shared, json);
    outputs.push_back(std::move(json));
  }
  for (const CapturedLog::Line& log : harness.log.lines()) {
    outputs.push_back(fmt::format("{} {}", log.time.count(), log.message));
  }
  return outputs;
}

TEST(Player, SameInputsGiveTheSameOutputSequence) {
  const std::vector<std::string> first = run_once();
  const std::vector<std::string> second = run_once();
  EXPECT_GT(first.size(), 600u);
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace ocp::testing
