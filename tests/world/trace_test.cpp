// The JSON Lines trace (docs/trace-format.md): what it records, that each line is valid JSON
// with the stable fields, that the text form is rendered from it, and a golden trace of a
// short seeded world that fails when the trace changes unintentionally.
//
// An intended change regenerates the golden file with one command (docs/trace-format.md):
//   OCP_UPDATE_GOLDEN=1 build/tests/world_tests --gtest_filter='WorldGoldenTrace.*'
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

TEST(WorldTrace, RecordsTheRunFromItsFirstEventAsValidJsonLines) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{200});
  sim.world().drop_vehicle_connection("truck-1");
  sim.run_for(Millis{300});
  const TraceRecorder& trace = sim.trace();
  if (std::getenv("OCP_PRINT_TRACE")) std::fputs(trace.text().c_str(), stdout);

  const auto opened = trace.lines_containing(R"("event":"connection","wire":"vehicle","change":"opened")");
  ASSERT_EQ(opened.size(), 2u);
  EXPECT_EQ(TraceRecorder::line_time(opened[0]), SimTime{0}) << "subscribed before start: time-zero events are there";
  EXPECT_EQ(TraceRecorder::line_time(opened[1]), SimTime{Millis{300}});
  const auto closed = trace.lines_containing(R"("change":"closed")");
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_EQ(TraceRecorder::line_time(closed[0]), SimTime{Millis{200}});
  EXPECT_NE(closed[0].find(R"("reason":"peer.closed_by_peer")"), std::string::npos) << closed[0];
  EXPECT_EQ(first_trace_time(trace, R"("fault":"VehicleNoResponse","active":true)", SimTime{1}),
            SimTime{Millis{200}});
  // One latency sample per control tick: 0, 10, …, 500 ms.
  EXPECT_EQ(trace.lines_containing(R"("event":"latency")").size(), 51u);

  const auto lines = split_lines(trace.jsonl());
  ASSERT_EQ(lines.size(), trace.lines());
  EXPECT_EQ(lines[0], R"({"t_us":0,"source":"trace","event":"trace_format","version":1})");
  SimTime previous{0};
  for (const std::string& line : lines) {
    rapidjson::Document document;
    document.Parse(line.c_str());
    ASSERT_FALSE(document.HasParseError()) << line;
    ASSERT_TRUE(document.IsObject()) << line;
    ASSERT_TRUE(document["t_us"].IsInt64()) << line;
    ASSERT_TRUE(document["source"].IsString()) << line;
    ASSERT_TRUE(document["event"].IsString()) << line;
    EXPECT_GE(SimTime{document["t_us"].GetInt64()}, previous) << "time never goes back: " << line;
    previous = SimTime{document["t_us"].GetInt64()};
  }
}

TEST(WorldTrace, TextFormIsRenderedLineForLineFromTheJsonLines) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{50});
  const auto json_lines = split_lines(sim.trace().jsonl());
  const auto text_lines = split_lines(sim.trace().text());
  ASSERT_EQ(json_lines.size(), text_lines.size());
  for (std::size_t i = 0; i < text_lines.size(); ++i) {
    EXPECT_EQ(text_lines[i].substr(0, 12), fmt::format("{:>12}", TraceRecorder::line_time(json_lines[i]).count()));
    EXPECT_EQ(text_lines[i].find("unknown event"), std::string::npos) << text_lines[i];
  }
  EXPECT_EQ(render_trace_text("not json\n"), "? not json\n") << "a foreign line is shown, not dropped";
  const std::string text = sim.trace().text();
  EXPECT_NE(text.find("streamer:truck-1 vehicle connection opened pipe:vehicle-client:truck-1"), std::string::npos)
      << text;
  EXPECT_NE(text.find("streamer:truck-1 fault VehicleNoResponse raised"), std::string::npos) << text;
}

TEST(WorldTrace, LogLinesAreNotPartOfTheTrace) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{100});
  ASSERT_FALSE(sim.log().lines_containing("vehicle connected").empty()) << "the log has it";
  EXPECT_TRUE(sim.trace().lines_containing("vehicle connected").empty()) << "the trace does not";
}

TEST(WorldTrace, OptionsLeaveOutWholeEventKinds) {
  TraceOptions options;
  options.frames = false;
  options.link_messages = false;
  options.latency_samples = false;
  VirtualWorld sim(one_vehicle_config(), options);
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{100});
  EXPECT_TRUE(sim.trace().lines_containing(R"("event":"frame")").empty());
  EXPECT_TRUE(sim.trace().lines_containing(R"("event":"link")").empty());
  EXPECT_TRUE(sim.trace().lines_containing(R"("event":"latency")").empty());
  EXPECT_FALSE(sim.trace().lines_containing(R"("event":"fault")").empty());
}

TEST(WorldTrace, PlayerEventsCoverSourceLockingGamepadAndActiveVehicle) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{50});
  ClientOcpShared data;
  data.client_user_data["truck-1"].user_data = RawJson{R"({"cmd":1})"};
  sim.world().player().handle_client_data(ClientSource::plugin, data);
  sim.run_for(Millis{10});
  sim.world().player().handle_client_data(ClientSource::webview, data);
  sim.world().player().gamepad().unplug();
  sim.run_for(Millis{20});
  const TraceRecorder& trace = sim.trace();
  EXPECT_EQ(first_trace_time(trace, R"("event":"source_locked","source":"plugin")"), SimTime{Millis{50}});
  EXPECT_EQ(first_trace_time(trace, R"("event":"source_conflict","locked":"plugin","offending":"webview")"),
            SimTime{Millis{60}});
  EXPECT_EQ(first_trace_time(trace, R"("event":"active_vehicle","vehicle":"truck-1")"), SimTime{0});
  EXPECT_EQ(first_trace_time(trace, R"("event":"gamepad","plugged":true)"), SimTime{0});
  // Sampled by the Player frame: the frame at 60 ms ran before the unplug, the next one sees it.
  EXPECT_EQ(first_trace_time(trace, R"("event":"gamepad","plugged":false)"), SimTime{Millis{70}});
  EXPECT_EQ(first_trace_time(trace, R"("side":"operator","vehicle":"truck-1","fault":"InputLost","active":true)"),
            SimTime{Millis{70}});
}

// The short seeded world of the golden trace: jitter, loss and a gamepad wave on one vehicle,
// 300 ms with an impairment change and a reconnect, so every common event kind appears.
std::string golden_world_trace() {
  WorldConfig config = one_vehicle_config(424242);
  config.vehicles[0].to_streamer = jittery_lossy_link();
  config.vehicles[0].to_player = jittery_lossy_link();
  VirtualWorld sim(config);
  EXPECT_TRUE(sim.start());
  Waveform waveform;
  waveform.waves.push_back(SineWave{GamepadAxis::left_x, 0.5, Millis{200}, 0.0});
  sim.world().player().gamepad().set_waveform(waveform);
  sim.run_for(Millis{150});
  sim.world().link("truck-1").to_player().set_impairments(delay_of(Millis{40}));
  sim.world().drop_vehicle_connection("truck-1");
  sim.run_for(Millis{150});
  return sim.trace().jsonl();
}

TEST(WorldTrace, PairRejectedCarriesBothPairsTheCauseAndTheHint) {
  const PairJudgement judgement{PairCause::rounded_through_double, AckPair{9'007'199'254'740'993ULL, 42u}};
  const std::string hint = "ack_time differs by 1 from issued pair: rounded through a double?";
  const Event event{SimTime{1500}, Component{ComponentKind::streamer, "truck-1"},
                    PairRejected{AckPair{9'007'199'254'740'992ULL, 42u}, judgement, hint}};
  std::string line;
  append_trace_line(event, TraceOptions{}, line);
  EXPECT_EQ(line,
            R"({"t_us":1500,"source":"streamer:truck-1","event":"pair_rejected",)"
            R"("rejected":{"ack_time":9007199254740992,"ack_time_mac":42},)"
            R"("nearest_issued":{"ack_time":9007199254740993,"ack_time_mac":42},)"
            R"("cause":"rounded_through_double","hint":")" + hint + "\"}\n");
  EXPECT_NE(render_trace_text(line).find("pair rejected (rounded_through_double): " + hint), std::string::npos)
      << render_trace_text(line);
}

TEST(WorldGoldenTrace, ShortSeededWorldMatchesTheCheckedInTrace) {
  const std::string path = std::string(OCP_TEST_DATA_DIR) + "/golden/short_world.jsonl";
  const std::string actual = golden_world_trace();
  if (std::getenv("OCP_UPDATE_GOLDEN")) {
    std::ofstream(path, std::ios::binary) << actual;
    GTEST_SKIP() << "rewrote " << path;
  }
  std::ifstream file(path, std::ios::binary);
  ASSERT_TRUE(file) << "missing " << path << "; create it with OCP_UPDATE_GOLDEN=1";
  const std::string expected((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (actual == expected) return;
  const auto want = split_lines(expected);
  const auto got = split_lines(actual);
  std::size_t line = 0;
  while (line < want.size() && line < got.size() && want[line] == got[line]) ++line;
  FAIL() << "the trace of the golden world changed at line " << line + 1 << ":\n  expected: "
         << (line < want.size() ? want[line] : "<end>") << "\n  actual:   "
         << (line < got.size() ? got[line] : "<end>")
         << "\nIf the change is intended, regenerate it: OCP_UPDATE_GOLDEN=1 build/tests/world_tests "
            "--gtest_filter='WorldGoldenTrace.*' (docs/trace-format.md)";
}

TEST(WorldGoldenTrace, TheGoldenWorldCoversEveryCommonEventKind) {
  const std::string trace = golden_world_trace();
  for (const char* kind : {"frame", "fault", "connection", "latency", "link", "impairments",
                           "gamepad", "active_vehicle"}) {
    EXPECT_NE(trace.find(std::string(R"("event":")") + kind + "\""), std::string::npos) << kind;
  }
  EXPECT_NE(trace.find(R"("outcome":"dropped")"), std::string::npos);
}

}  // namespace
}  // namespace ocp::world_test
