// The world generator and the scenario YAML writer (issue #21): the same campaign seed gives
// the same worlds; a generated world written as YAML parses back to the same world; worlds
// stay inside their profile's ranges and use every action kind.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "campaign/generator.hpp"
#include "campaign/world_facts.hpp"
#include "scenario/parse.hpp"
#include "scenario/write.hpp"

namespace ocp::campaign {
namespace {

// A generated world has no expectation; a scenario file needs one.
scenario::Scenario with_expectation(scenario::Scenario world) {
  world.expectations.push_back(
      {"", {}, scenario::InvariantExpectation{scenario::Invariant::default_controller_during_control_fault}});
  return world;
}

// The names of what a misbehaviour event switches on.
void note_misbehaviour_kinds(const scenario::SetMisbehaviour& set, std::set<std::string>& kinds) {
  const Misbehaviour& m = set.misbehave;
  if (m.stop_echo) kinds.insert("stop_echo");
  if (m.corrupt_mac) kinds.insert("corrupt_mac");
  if (m.delay_responses > Micros{0}) kinds.insert("delay_responses");
  if (m.oversized_frames) kinds.insert("oversized_frames");
  if (m.ack_through_double) kinds.insert("ack_through_double");
  if (m.malformed_json) kinds.insert("malformed_json");
  if (m.silent) kinds.insert("silent");
  if (m.bad_response != BadResponse::none) kinds.insert(std::string(bad_response_name(m.bad_response)));
  if (set.second_connection) kinds.insert("second_connection");
}

// The same for the operator port's misbehaviours.
void note_operator_kinds(const scenario::SetOperatorMisbehaviour& set, std::set<std::string>& kinds) {
  const scenario::OperatorMisbehaviour& m = set.misbehave;
  if (m.silent) kinds.insert("silent");
  if (m.malformed_json) kinds.insert("malformed_json");
  if (m.oversized_frames) kinds.insert("oversized_frames");
  if (m.bad_message != scenario::BadClientMessage::none) kinds.insert(std::string(bad_client_message_name(m.bad_message)));
  if (set.second_connection) kinds.insert("second_connection");
}

TEST(CampaignGenerator, SameSeedSameWorlds) {
  const Profile profile = load_profile(shipped_profile_path("default"));
  for (std::uint64_t index = 0; index < 20; ++index) {
    EXPECT_EQ(scenario::write_scenario_yaml(with_expectation(generate_world(profile, 42, index))),
              scenario::write_scenario_yaml(with_expectation(generate_world(profile, 42, index))));
  }
  EXPECT_NE(scenario::write_scenario_yaml(with_expectation(generate_world(profile, 42, 0))),
            scenario::write_scenario_yaml(with_expectation(generate_world(profile, 43, 0))));
  EXPECT_NE(world_seed(42, 0), world_seed(42, 1));
}

TEST(CampaignGenerator, WrittenWorldParsesBackToTheSameWorld) {
  const Profile profile = load_profile(shipped_profile_path("default"));
  for (std::uint64_t index = 0; index < 50; ++index) {
    const std::string first = scenario::write_scenario_yaml(with_expectation(generate_world(profile, 9, index)));
    const scenario::Scenario parsed = scenario::parse_scenario(first, "world.yaml");
    EXPECT_EQ(scenario::write_scenario_yaml(parsed), first) << "world " << index;
  }
}

TEST(CampaignGenerator, WorldsStayInTheirRangesAndUseEveryAction) {
  const Profile profile = load_profile(shipped_profile_path("default"));
  std::set<std::size_t> actions;
  std::set<std::string> misbehaviours, operator_misbehaviours;
  bool monitor = false, fleet = false;
  int operator_clients = 0;
  for (std::uint64_t index = 0; index < 300; ++index) {
    const scenario::Scenario world = generate_world(profile, 5, index);
    EXPECT_GE(world.duration, profile.duration.min);
    EXPECT_LE(world.duration, profile.duration.max);
    EXPECT_GE(world.world.vehicles.size(), 1u);
    EXPECT_LE(world.world.vehicles.size(), 4u);
    EXPECT_FALSE(world.world.vehicles.front().monitor);
    if (world.operator_client.connect) {
      ++operator_clients;
      EXPECT_GE(world.operator_client.keep_alive_period, profile.operator_keep_alive_period.min);
      EXPECT_LE(world.operator_client.keep_alive_period, profile.operator_keep_alive_period.max);
    }
    fleet = fleet || world.world.vehicles.size() > 1;
    for (const VehicleSpec& spec : world.world.vehicles) {
      monitor = monitor || spec.monitor;
      EXPECT_GE(spec.streamer.latency_limit, profile.latency_limit.min);
      EXPECT_LE(spec.streamer.latency_limit, profile.latency_limit.max);
    }
    for (const scenario::TimelineEvent& event : world.timeline) {
      actions.insert(event.action.index());
      EXPECT_LT(event.at, world.duration - liveness_bound(world) + Micros{1});
      if (const auto* set = std::get_if<scenario::SetMisbehaviour>(&event.action)) note_misbehaviour_kinds(*set, misbehaviours);
      if (const auto* set = std::get_if<scenario::SetOperatorMisbehaviour>(&event.action)) {
        EXPECT_TRUE(world.operator_client.connect) << "world " << index;
        note_operator_kinds(*set, operator_misbehaviours);
      }
    }
  }
  // About operator_client_share (0.5) of the worlds have an operator client.
  EXPECT_GT(operator_clients, 100);
  EXPECT_LT(operator_clients, 200);
  EXPECT_TRUE(monitor);
  EXPECT_TRUE(fleet);
  EXPECT_EQ(actions.size(), std::variant_size_v<scenario::Action>);
  // Every misbehaviour of the format: 7 switches, 5 broken responses, a second connection.
  EXPECT_EQ(misbehaviours.size(), 13u) << ::testing::PrintToString(misbehaviours);
  // And on the operator port: silence, malformed JSON, oversized, 3 bad messages, a second connection.
  EXPECT_EQ(operator_misbehaviours.size(), 7u) << ::testing::PrintToString(operator_misbehaviours);
}

// Besides a fleet's first selection at 0 s, which every fleet world needs.
TEST(CampaignGenerator, CalmProfileHasImpairmentsOnly) {   // and keep-alives, where an operator client is on
  const Profile profile = load_profile(shipped_profile_path("calm"));
  for (std::uint64_t index = 0; index < 100; ++index) {
    for (const scenario::TimelineEvent& event : generate_world(profile, 5, index).timeline) {
      const bool first_selection = std::holds_alternative<scenario::SelectVehicle>(event.action) && event.at == SimTime{0};
      EXPECT_TRUE(std::holds_alternative<scenario::SetImpairments>(event.action) || first_selection);
    }
  }
}

// Every library scenario survives a write and a parse (the writer knows the whole format).
TEST(CampaignGenerator, LibraryScenariosRoundTrip) {
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(OCP_SCENARIO_LIBRARY_DIR)) {
    ++files;
    const scenario::Scenario original = scenario::load_scenario(entry.path().string());
    const std::string written = scenario::write_scenario_yaml(original);
    const scenario::Scenario parsed = scenario::parse_scenario(written, entry.path().filename().string());
    EXPECT_EQ(scenario::write_scenario_yaml(parsed), written) << entry.path();
    EXPECT_EQ(parsed.expectations.size(), original.expectations.size()) << entry.path();
  }
  EXPECT_GT(files, 0u) << "no scenario in " << OCP_SCENARIO_LIBRARY_DIR << ": the round trip proved nothing";
}

}  // namespace
}  // namespace ocp::campaign
