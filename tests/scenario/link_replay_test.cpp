// Replay of a recorded run (docs/link-recording.md): extract-link turns a run's trace into a
// link recording, `link: {replay: FILE}` replays it, and the replayed run's latency series is
// the original's. Also: how `replay:` is read, and what extract-link refuses.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ocp/link_recording.hpp"
#include "scenario/extract_link.hpp"
#include "scenario_test_support.hpp"
#include "scratch_dir.hpp"

namespace ocp::scenario {
namespace {

namespace fs = std::filesystem;

class ScenarioLinkReplay : public ::testing::Test {
 protected:
  void write(const std::string& name, const std::string& text) { std::ofstream(folder_ / name) << text; }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  // One vehicle with the given link lines, driving; `duration` of virtual time.
  static std::string story(const std::string& link, const std::string& rest = "", const std::string& duration = "8s") {
    return "seed: 11\nduration: " + duration +
           "\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n      latency_limit: 300ms\n" + link + rest +
           "expect: {invariants: [no_stale_pair_after_reconnect]}\n";
  }
  // Runs `yaml` (written as `name`) and returns the run.
  RunResult run(const std::string& name, const std::string& yaml) {
    write(name, yaml);
    return run_scenario(load_scenario(path(name)), RunOptions{});
  }
  std::string extract(const RunResult& original, const std::string& vehicle = "truck-1") {
    write("trace.jsonl", original.trace_jsonl);
    const ExtractedLink extracted = extract_link(original.trace_jsonl, ExtractLinkOptions{path("trace.jsonl"), vehicle, false});
    return extracted.recording.format(extracted.comments);
  }
  testing_support::ScratchDir scratch_{"ocp_link_replay_test"};
  fs::path folder_ = scratch_.path();
};

// The issue's acceptance test: jitter, loss and a timeline change in the original; the replay
// has only the recording, and its latency series is the original's within 1 ms per sample.
TEST_F(ScenarioLinkReplay, ReplayReproducesTheOriginalLatencySeries) {
  const RunResult original = run("original.yaml", story(
      "      link: {delay: 25ms, jitter: 8ms, jitter_kind: normal, loss: 0.03}\n",
      "timeline:\n  - at: 3s\n    impair: {direction: to_player, delay: 120ms, loss: 0.2}\n"
      "  - at: 5s\n    impair: {direction: to_player, delay: 30ms, loss: 0.01}\n"));
  write("drive.link", extract(original));
  const RunResult replayed = run("replayed.yaml", story("      link: {replay: drive.link}\n"));

  const auto& before = original.observations.vehicles.at("truck-1").latency_ms.points();
  const auto& after = replayed.observations.vehicles.at("truck-1").latency_ms.points();
  ASSERT_GT(before.size(), 500u);
  ASSERT_EQ(after.size(), before.size());
  double worst = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    ASSERT_EQ(after[i].time, before[i].time) << "sample " << i;
    worst = std::max(worst, std::fabs(after[i].value - before[i].value));
  }
  EXPECT_LE(worst, 1.0);
  // And the recording did matter: the 120 ms stretch shows in both.
  const auto peak = std::max_element(before.begin(), before.end(), [](auto& a, auto& b) { return a.value < b.value; });
  EXPECT_GT(peak->value, 140.0);
  EXPECT_EQ(replayed.observations.vehicles.at("truck-1").to_player.dropped,
            original.observations.vehicles.at("truck-1").to_player.dropped);
}

// Without the replay (the same link minus the timeline) the series differs: the test can fail.
TEST_F(ScenarioLinkReplay, ADifferentLinkGivesADifferentSeries) {
  const RunResult original = run("original.yaml", story("      link: {delay: 25ms, jitter: 8ms}\n",
                                                        "timeline:\n  - at: 3s\n    impair: {delay: 120ms}\n"));
  const RunResult other = run("other.yaml", story("      link: {delay: 25ms, jitter: 8ms}\n"));
  const auto& a = original.observations.vehicles.at("truck-1").latency_ms.points();
  const auto& b = other.observations.vehicles.at("truck-1").latency_ms.points();
  double worst = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) worst = std::max(worst, std::fabs(a[i].value - b[i].value));
  EXPECT_GT(worst, 50.0);
}

// After the recording's last message the replay loops: message n gets entry n mod size.
TEST_F(ScenarioLinkReplay, TheRecordingLoops) {
  write("short.link", "ocp-link-recording 1\nto_streamer 0 10000\nto_streamer 1 lost\nto_player 0 40000\n");
  const RunResult replayed = run("replayed.yaml", story("      link: {replay: short.link}\n", "", "2s"));
  const VehicleObservations& truck = replayed.observations.vehicles.at("truck-1");
  EXPECT_GT(truck.to_streamer.sent, 100u);
  // Every second control message is lost (entry 1 of 2), none of the uplink's.
  EXPECT_NEAR(static_cast<double>(truck.to_streamer.dropped), static_cast<double>(truck.to_streamer.sent) / 2, 1.0);
  EXPECT_EQ(truck.to_player.dropped, 0u);
}

TEST_F(ScenarioLinkReplay, PerDirectionAndCheckedAgainstTheRecording) {
  write("up_only.link", "ocp-link-recording 1\nto_player 0 40000\n");
  write("ok.yaml", story("      to_player: {replay: up_only.link}\n"));
  const Scenario scenario = load_scenario(path("ok.yaml"));
  EXPECT_TRUE(scenario.world.vehicles.at(0).to_player.replay);
  EXPECT_FALSE(scenario.world.vehicles.at(0).to_streamer.replay);
  write("bad.yaml", story("      link: {replay: up_only.link}\n"));
  try {
    load_scenario(path("bad.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_NE(std::string(error.what()).find("has no to_streamer messages"), std::string::npos) << error.what();
    EXPECT_EQ(error.line(), 8);
  }
  // The direction's own block, without a replay of its own, does not hide where the replay is named.
  write("bad2.yaml", story("      link: {replay: up_only.link}\n      to_streamer: {down: false}\n"));
  try {
    load_scenario(path("bad2.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_EQ(error.line(), 8) << error.what();
  }
}

TEST_F(ScenarioLinkReplay, ReplayExcludesTheOtherSettingsAndABadFileNamesItsLine) {
  write("a.link", "ocp-link-recording 1\nto_player 0 40000\nto_streamer 0 -5\n");
  write("mixed.yaml", story("      link: {replay: a.link, delay: 20ms}\n"));
  try {
    load_scenario(path("mixed.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_NE(std::string(error.what()).find("replay and delay exclude each other"), std::string::npos) << error.what();
  }
  write("bad.yaml", story("      link: {replay: a.link}\n"));
  try {
    load_scenario(path("bad.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(path("a.link") + ":3: expected a delay", 0), 0u) << error.what();
  }
}

TEST_F(ScenarioLinkReplay, ExtractRefusesBadInputWithFileAndLine) {
  write("bad.jsonl", std::string(R"({"t_us":0,"source":"trace","event":"trace_format","version":1})") + "\nnot json\n");
  std::ostringstream out, err;
  EXPECT_EQ(extract_link_command(ExtractLinkOptions{path("bad.jsonl"), "truck-1", false}, out, err), 2);
  EXPECT_NE(err.str().find(path("bad.jsonl") + ":2: not a JSON object"), std::string::npos) << err.str();
  EXPECT_TRUE(out.str().empty());
}

TEST_F(ScenarioLinkReplay, ExtractListsTheKnownVehiclesForAnUnknownOne) {
  const RunResult original = run("original.yaml", story("      link: {delay: 25ms}\n", "", "1s"));
  write("trace.jsonl", original.trace_jsonl);
  std::ostringstream out, err;
  EXPECT_EQ(extract_link_command(ExtractLinkOptions{path("trace.jsonl"), "truck-9", false}, out, err), 2);
  EXPECT_NE(err.str().find("unknown vehicle 'truck-9'; the trace has: truck-1"), std::string::npos) << err.str();
  // Without --vehicle, the only vehicle is taken.
  std::ostringstream out2, err2;
  EXPECT_EQ(extract_link_command(ExtractLinkOptions{path("trace.jsonl"), "", false}, out2, err2), 0) << err2.str();
  EXPECT_NE(out2.str().find("to_player 0 "), std::string::npos);
}

// Different clocks (a two-host run): every delay is the loop's RTT/2, and the header says so.
TEST_F(ScenarioLinkReplay, RttHalfWhenTheClocksDiffer) {
  const RunResult original = run("original.yaml", story("      link: {delay: 40ms}\n", "", "2s"));
  const ExtractedLink extracted =
      extract_link(original.trace_jsonl, ExtractLinkOptions{path("trace.jsonl"), "truck-1", true});
  EXPECT_EQ(extracted.recording.clock(LinkRoute::to_player), LinkRecording::Clock::rtt_half);
  const std::string text = extracted.recording.format(extracted.comments);
  EXPECT_NE(text.find("delay = RTT/2"), std::string::npos);
  EXPECT_NE(text.find("clock to_player rtt_half"), std::string::npos);
  // The loop is 80 ms of link plus the waits for a Player frame and a control tick (10 ms
  // each, at most a few of them): RTT/2 ≈ 40–60 ms, and never the measured 40 ms alone.
  const auto& late = extracted.recording.route(LinkRoute::to_player).back();
  EXPECT_GT(late.delay, Micros{40'000});
  EXPECT_LE(late.delay, Micros{60'000});
}

// The library's replayed story replays the committed recording of its source run, and gets
// that run's latency series back (a stale recording fails here and in link_traces_fresh).
TEST(ScenarioLibraryReplay, ReplayedDriveReproducesItsSourceRun) {
  const std::string library = OCP_SCENARIO_LIBRARY_DIR;
  const Scenario source = load_scenario(library + "/../traces/replayed_drive.source.yaml");
  const Scenario replay = load_scenario(library + "/replayed_drive.yaml");
  ASSERT_TRUE(replay.world.vehicles.at(0).to_player.replay);
  EXPECT_TRUE(replay.world.vehicles.at(0).to_player.replay->name().ends_with("replayed_drive.link"));
  RunOptions options;
  options.trace = false;
  const RunResult original = run_scenario(source, options), replayed = run_scenario(replay, options);
  const auto& before = original.observations.vehicles.at("truck-1").latency_ms.points();
  const auto& after = replayed.observations.vehicles.at("truck-1").latency_ms.points();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    ASSERT_EQ(after[i].time, before[i].time) << "sample " << i;
    ASSERT_LE(std::fabs(after[i].value - before[i].value), 1.0) << "sample " << i << " at " << before[i].time.count() << " µs";
  }
}

}  // namespace
}  // namespace ocp::scenario
