// The conformance library's pure parts: hand-made frames, case selection, baseline, port
// substitution, report formats, the case table.
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <fstream>
#include <set>

#include "conformance/baseline.hpp"
#include "sim_app/client_process.hpp"
#include "conformance/control_frames.hpp"
#include "conformance/observations.hpp"
#include "conformance/reports.hpp"
#include "conformance/runner.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::conformance {
using sim_app::ClientProcess;
using sim_app::substitute_port;
namespace {

TEST(ControlFrames, EveryShapeDecodesWithTheProtocolCodec) {
  for (auto controller : {CraftedController::driving, CraftedController::null, CraftedController::safe_default, CraftedController::absent}) {
    for (bool unknown : {false, true}) {
      CraftedControl control{AckPair{~std::uint64_t{0}, 0xFFFFFFFFu}};
      control.controller = controller;
      control.unknown_fields = unknown;
      control.fault = true;
      control.client_user_data = nested_user_data(16);
      const auto decoded = decode_control_message(control_payload(control));
      ASSERT_TRUE(decoded.ok()) << decoded.error().message() << "\n" << control_payload(control);
      EXPECT_EQ(decoded->ack, control.ack);   // u64 max survives byte-exact
      EXPECT_EQ(decoded->controller.has_value(), controller != CraftedController::null && controller != CraftedController::absent);
      if (controller == CraftedController::safe_default) {
        EXPECT_TRUE(decoded->controller->is_safe_default());
      }
      EXPECT_TRUE(decoded->telemetry.fault);
    }
  }
}

// vehicle/3.2/4's forms are ones the product may send: the protocol codec reads every one.
TEST(ControlFrames, TheProductsOtherShapesDecodeWithTheProtocolCodec) {
  CraftedControl control{AckPair{1, 2}};
  control.controller = CraftedController::absent;
  control.client_user_data = "null";
  control.missing_cameras.clear();
  const std::string bare = control_payload(control);
  EXPECT_EQ(bare.find("controller"), std::string::npos) << bare;
  EXPECT_EQ(bare.find("missing_cameras"), std::string::npos) << bare;
  ASSERT_TRUE(decode_control_message(bare).ok()) << bare;
  control.missing_cameras = R"(["rear"])";
  const auto lost = decode_control_message(control_payload(control));
  ASSERT_TRUE(lost.ok()) << control_payload(control);
  EXPECT_EQ(lost->telemetry.missing_cameras, std::vector<std::string>{"rear"});
}

TEST(ControlFrames, FramesCarryALittleEndianPrefix) {
  const std::string frame = frame_bytes("{}");
  ASSERT_EQ(frame.size(), 6u);
  EXPECT_EQ(frame.substr(0, 4), std::string("\x02\x00\x00\x00", 4));
  const std::string big = oversized_frame(20000);
  EXPECT_EQ(big.size(), 20004u);
  EXPECT_EQ(static_cast<unsigned char>(big[0]) | static_cast<unsigned char>(big[1]) << 8, 20000);
}

TEST(CaseSelection, IdsPrefixesAndGlobs) {
  EXPECT_TRUE(matches_any("vehicle/3.3/1", "vehicle/3.3/1"));
  EXPECT_TRUE(matches_any("vehicle/3.3/1", "vehicle/3.3"));
  EXPECT_FALSE(matches_any("vehicle/3.3/1", "vehicle/3"));   // a prefix is a whole section
  EXPECT_TRUE(matches_any("vehicle/3.3/1", "vehicle/3*"));
  EXPECT_TRUE(matches_any("vehicle/2/7", "x,vehicle/2/?"));
  EXPECT_FALSE(matches_any("vehicle/2/7", ""));
  const auto all = vehicle_cases();
  const auto some = select_cases(all, "vehicle/2", "vehicle/2/3");
  for (const auto& c : some) {
    EXPECT_EQ(c.body.info.id.rfind("vehicle/2/", 0), 0u);
    EXPECT_NE(c.body.info.id, "vehicle/2/3");
  }
  EXPECT_FALSE(some.empty());
}

TEST(Cases, StableUniqueIdsWithEverythingACaseNeeds) {
  std::set<std::string> ids;
  for (const auto& c : vehicle_cases()) {
    const CaseInfo& info = c.body.info;
    EXPECT_TRUE(ids.insert(info.id).second) << info.id;
    EXPECT_EQ(info.id.rfind("vehicle/", 0), 0u);
    EXPECT_FALSE(info.requirement.empty()) << info.id;
    EXPECT_FALSE(info.source.empty()) << info.id;
    EXPECT_FALSE(info.expected.empty()) << info.id;
    EXPECT_FALSE(info.broken_by.empty()) << info.id << ": every case must be able to fail";
    EXPECT_GT(info.timeout.count(), 0) << info.id;
    EXPECT_TRUE(c.body.run) << info.id;
  }
  EXPECT_GE(ids.size(), 16u);
}

CaseResult result(std::string id, Tier tier, Verdict verdict) {
  CaseResult r;
  r.info.id = std::move(id);
  r.info.tier = tier;
  r.info.title = "t";
  r.info.requirement = "req <b>";
  r.info.expected = {"OK: x"};
  r.verdict = verdict;
  r.actual = "actual \"quoted\"";
  return r;
}

TEST(Baseline, ExitCodeAndDiff) {
  const std::vector<CaseResult> results{result("a", Tier::must, Verdict::failed),
                                        result("b", Tier::should, Verdict::failed),
                                        result("c", Tier::must, Verdict::ok)};
  EXPECT_EQ(exit_code(results, nullptr), 1);
  const Baseline expected{"a", "c"};
  EXPECT_EQ(exit_code(results, &expected), 0);
  const BaselineDiff diff = diff_baseline(expected, results);
  EXPECT_EQ(diff.new_failures, std::vector<std::string>{"b"});
  EXPECT_EQ(diff.still_failing, std::vector<std::string>{"a"});
  EXPECT_EQ(diff.fixed, std::vector<std::string>{"c"});
  const std::string path = ::testing::TempDir() + "/baseline.txt";
  std::ofstream(path) << baseline_text(results) << "\n# comment only\n";
  const auto loaded = load_baseline(path);
  ASSERT_TRUE(loaded.ok());
  EXPECT_EQ(*loaded, (Baseline{"a", "b"}));
  EXPECT_FALSE(load_baseline("/nonexistent/baseline").ok());
}

TEST(Launcher, PortIsSubstitutedEverywhere) {
  EXPECT_EQ(substitute_port({"client", "127.0.0.1:{port}", "--p={port}{port}"}, 4100),
            (std::vector<std::string>{"client", "127.0.0.1:4100", "--p=41004100"}));
}

TEST(Launcher, MissingExecutableIsAnError) {
  const auto launched = ClientProcess::launch({"/nonexistent/client"}, 1, "");
  EXPECT_FALSE(launched.ok());
}

TEST(Launcher, ChildIsKilled) {
  auto launched = ClientProcess::launch({"sleep", "60"}, 1, "");
  ASSERT_TRUE(launched.ok());
  auto& child = *launched;
  EXPECT_TRUE(child->running());
  child->kill();
  EXPECT_FALSE(child->running());
  ASSERT_TRUE(child->exit_status().has_value());
}

TEST(Reports, JsonHtmlAndJunitAreWellFormed) {
  RunSummary summary;
  summary.results = {result("vehicle/1", Tier::must, Verdict::failed), result("vehicle/2", Tier::should, Verdict::non_strict)};
  WireLogEntry entry;
  entry.kind = WireEntryKind::in;
  entry.text = std::string("bad\x01\"bytes<", 11);
  entry.ack = AckPair{~std::uint64_t{0}, 7};
  summary.results[0].wire_log.push_back(entry);
  summary.duration_ms = 12.5;
  ReportContext context{"vehicle", "client --x", &summary, nullptr};
  rapidjson::Document doc;
  const std::string json = index_json(context);
  doc.Parse(json.c_str());
  ASSERT_FALSE(doc.HasParseError()) << json;
  EXPECT_EQ(doc["exit_code"].GetInt(), 1);
  ASSERT_EQ(doc["cases"].Size(), 2u);
  EXPECT_STREQ(doc["cases"][0]["verdict"].GetString(), "FAILED");
  EXPECT_EQ(doc["cases"][0]["wire_log"][0]["ack_time"].GetUint64(), ~std::uint64_t{0});
  const std::string html = html_report(context);
  EXPECT_NE(html.find("id=\"vehicle/1\""), std::string::npos);
  EXPECT_NE(html.find("bad?&quot;bytes&lt;"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);   // self-contained, static
  const std::string xml = junit_xml(context);
  EXPECT_NE(xml.find("tests=\"2\" failures=\"1\""), std::string::npos);
  EXPECT_NE(xml.find("<failure"), std::string::npos);
}

TEST(Observations, PercentilesAndLookups) {
  EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5}, 50), 3.0);
  EXPECT_DOUBLE_EQ(percentile({}, 50), 0.0);
  std::vector<WireLogEntry> log(3);
  log[0].kind = WireEntryKind::out;
  log[0].time_us = 10;
  log[0].ack = AckPair{1, 1};
  log[1].kind = WireEntryKind::out;
  log[1].time_us = 20;
  log[1].ack = AckPair{2, 2};
  log[2].kind = WireEntryKind::in;
  log[2].time_us = 25;
  log[2].ack = AckPair{1, 1};
  const Observations obs = Observations::from(log);
  EXPECT_EQ(obs.find_sent(AckPair{2, 2}), 1);
  EXPECT_EQ(obs.find_sent(AckPair{2, 3}), -1);
  EXPECT_EQ(obs.latest_sent_before(15), 0);
  EXPECT_EQ(obs.latest_sent_before(5), -1);
  EXPECT_EQ(obs.responses_with_pair(), 1u);
}

// The window rule (observations.hpp): per connection, what the client wrote before it read a
// control message — before our first frame, or crossing it on the wire, even in the same read
// as its first real echo — is set apart in before_control; other cases never grade it.
TEST(Observations, WindowOpensAtTheClientsFirstControlMessageOnEachConnection) {
  std::vector<WireLogEntry> log;
  const auto add = [&](WireEntryKind kind, std::int64_t time_us, std::optional<AckPair> ack = std::nullopt) {
    WireLogEntry entry;
    entry.kind = kind;
    entry.time_us = time_us;
    entry.ack = ack;
    log.push_back(entry);
  };
  const AckPair a{100, 1}, b{200, 2}, c{300, 3};
  add(WireEntryKind::opened, 0);
  add(WireEntryKind::in, 1, AckPair{0, 0});       // before any control frame
  add(WireEntryKind::out, 10, a);
  add(WireEntryKind::in, 12, AckPair{7, 7});      // crossed our first frame on the wire
  add(WireEntryKind::in, 12, a);                  // same read: the first real echo
  add(WireEntryKind::in, 15, AckPair{9, 9});      // after an echo: the client's own doing
  add(WireEntryKind::closed, 20);
  add(WireEntryKind::opened, 30);                 // a reconnect starts a new window
  add(WireEntryKind::out, 31, b);
  add(WireEntryKind::in, 33, AckPair{5, 5});
  add(WireEntryKind::in, 33, b);
  add(WireEntryKind::opened, 40);                 // never echoes: no crossing allowance
  add(WireEntryKind::in, 41, AckPair{6, 6});
  add(WireEntryKind::out, 42, c);
  add(WireEntryKind::in, 43, AckPair{8, 8});
  const Observations obs = Observations::from(log);
  const auto pairs = [](const std::vector<Response>& responses) {
    std::vector<std::uint64_t> out;
    for (const Response& r : responses) out.push_back(r.ack->ack_time);
    return out;
  };
  EXPECT_EQ(pairs(obs.before_control), (std::vector<std::uint64_t>{0, 7, 5, 6}));
  EXPECT_EQ(pairs(obs.responses), (std::vector<std::uint64_t>{100, 9, 200, 8}));
  EXPECT_EQ(pairs(obs.all_responses), (std::vector<std::uint64_t>{0, 7, 100, 9, 5, 200, 6, 8}));
  // A `since` inside a connection filters by time but keeps that connection's window.
  const Observations late = Observations::from(log, 12);
  EXPECT_EQ(pairs(late.before_control), (std::vector<std::uint64_t>{7, 5, 6}));
  EXPECT_EQ(pairs(late.responses), (std::vector<std::uint64_t>{100, 9, 200, 8}));
}

// The runner starts a case's body only once the client is connected. A client that never
// connects fails a MUST case, and leaves an INFO case with nothing measured; no body runs.
TEST(Runner, ACaseBodyStartsOnlyWithAConnectedClient) {
  bool body_ran = false;
  const auto body = [&body_ran](CaseContext&) {
    body_ran = true;
    return Outcome{Verdict::ok, "ran", {}};
  };
  std::vector<VehicleCase> cases;
  for (const Tier tier : {Tier::must, Tier::info}) {
    CaseInfo info;
    info.id = tier == Tier::must ? "test/1/1" : "test/1/2";
    info.tier = tier;
    info.timeout = std::chrono::milliseconds(20'000);  // scaled below: 1 s, after the 0.5 s wait
    cases.push_back({{info, body}, {}});
  }
  RunOptions options;
  options.port = 0;             // an external client that never comes
  options.timeout_scale = 0.05;  // the connection wait: 10 s → 0.5 s
  const RunSummary summary = run_cases(cases, options);
  ASSERT_EQ(summary.results.size(), 2u) << summary.harness_error;
  EXPECT_FALSE(body_ran);
  EXPECT_EQ(summary.results[0].verdict, Verdict::failed);
  EXPECT_EQ(summary.results[0].actual, "the client did not connect within 10 s");
  EXPECT_EQ(summary.results[1].verdict, Verdict::informational);
  EXPECT_EQ(summary.results[1].actual, "the client did not connect within 10 s: nothing measured");
}

}  // namespace
}  // namespace ocp::conformance
