// Client worlds exercise what a client must survive (issue #34 item 2), drawn from the world's
// seed: a Streamer-side close in every world of 10 s or more, ack_time above 2^53 in at least
// half the worlds, client_user_data up to the frame limit, controller: null, the default
// controller. Checked over 200 generated client worlds of the default profile.
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <set>

#include "campaign/client_world.hpp"
#include "campaign/generator.hpp"
#include "campaign/profile.hpp"
#include "scenario/parse.hpp"
#include "scenario/write.hpp"

namespace ocp::campaign {
namespace {

constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;
constexpr std::uint64_t two_to_63 = std::uint64_t{1} << 63;
constexpr int worlds = 200;

scenario::Scenario client_world(std::uint64_t index, std::optional<Micros> max = Micros{15'000'000}) {
  scenario::Scenario world = for_external_client(generate_world(load_profile(shipped_profile_path("default")), 17, index), index, max);
  // A scenario file needs an expectation (failure_files.cpp adds the same one to world.yaml).
  world.expectations.push_back({"", {}, scenario::InvariantExpectation{scenario::Invariant::default_controller_during_control_fault}});
  return world;
}

bool has(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

TEST(ClientHazards, EveryWorldOfTenSecondsClosesEveryVehicleFromTheStreamerSide) {
  int restarts = 0, plain = 0;
  for (std::uint64_t i = 0; i < worlds; ++i) {
    const scenario::Scenario world = client_world(i);
    ASSERT_GE(world.duration, Micros{10'000'000}) << "the default profile draws worlds of 10 s or more";
    std::set<std::string> closed;
    for (const scenario::TimelineEvent& event : world.timeline) {
      const auto* close = std::get_if<scenario::DisconnectVehicle>(&event.action);
      if (close == nullptr) continue;
      (close->listener_down > Micros{0} ? restarts : plain) += 1;
      // With room for the reconnect bound (5 s) after the port is back. (The generator's own
      // disconnects may come later: a late close is not judged, as the bound outlasts the world.)
      if (event.at + close->listener_down + Micros{5'000'000} <= world.duration) closed.insert(close->vehicle);
    }
    EXPECT_EQ(closed.size(), world.world.vehicles.size()) << "world " << i;
    EXPECT_TRUE(has(hazards_in(world), "streamer_close")) << "world " << i;
  }
  EXPECT_GT(restarts, worlds / 4);
  EXPECT_GT(plain, worlds / 4);
}

TEST(ClientHazards, AtLeastHalfTheWorldsSendAckTimeAbove2To53InEveryBand) {
  int high = 0;
  std::set<int> bands;
  for (std::uint64_t i = 0; i < worlds; ++i) {
    const scenario::Scenario world = client_world(i);
    const bool all_high = std::all_of(world.world.vehicles.begin(), world.world.vehicles.end(),
                                      [](const VehicleSpec& spec) { return spec.streamer.ack_time_offset >= two_to_53; });
    if (i % 2 == 0) {
      EXPECT_TRUE(all_high) << "every even world, world " << i;
    }
    high += all_high ? 1 : 0;
    // The generator alone gives some vehicles a high offset; the hazard names any.
    const bool any_high = std::any_of(world.world.vehicles.begin(), world.world.vehicles.end(),
                                      [](const VehicleSpec& spec) { return spec.streamer.ack_time_offset >= two_to_53; });
    EXPECT_EQ(any_high, has(hazards_in(world), "ack_time_above_2^53")) << "world " << i;
    for (const VehicleSpec& spec : world.world.vehicles) {
      const std::uint64_t offset = spec.streamer.ack_time_offset;
      if (offset < two_to_53) continue;
      bands.insert(offset >= two_to_63 + (two_to_63 - (std::uint64_t{1} << 42)) ? 2 : offset >= two_to_63 ? 1 : 0);
      // No ack_time of the world wraps past 2^64 − 1.
      EXPECT_LT(offset, ~std::uint64_t{0} - static_cast<std::uint64_t>(world.duration.count())) << "world " << i;
    }
  }
  EXPECT_GE(high, worlds / 2);
  EXPECT_EQ(bands.size(), 3u) << "above 2^53, above 2^63, just below 2^64";
}

TEST(ClientHazards, UserDataUpToTheFrameLimitNullControllersAndTheDefaultController) {
  int large = 0, null_controller = 0, control_fault = 0;
  for (std::uint64_t i = 0; i < worlds; ++i) {
    const scenario::Scenario world = client_world(i);
    for (const scenario::TimelineEvent& event : world.timeline) {
      const auto* data = std::get_if<scenario::ClientDataAction>(&event.action);
      if (data == nullptr || data->every != Micros{10'000} || !data->until) continue;   // the episode, not what follows
      for (const auto& [vehicle, entry] : data->vehicles) {
        ASSERT_TRUE(entry.user_data_json.has_value());
        rapidjson::Document parsed;
        parsed.Parse(entry.user_data_json->c_str(), entry.user_data_json->size());
        EXPECT_FALSE(parsed.HasParseError()) << "world " << i;
        EXPECT_LE(entry.user_data_json->size(), 15u * 1024 + 200) << "the control frame stays below 16 KiB";
        if (entry.user_data_json->size() >= 1024) {
          EXPECT_TRUE(std::any_of(entry.user_data_json->begin(), entry.user_data_json->end(),
                                  [](char c) { return static_cast<unsigned char>(c) >= 0x80; }))
              << "non-ASCII UTF-8, world " << i;
        }
      }
    }
    const std::vector<std::string> hazards = hazards_in(world);
    large += has(hazards, "user_data_over_8KiB") ? 1 : 0;
    null_controller += has(hazards, "controller_null") ? 1 : 0;
    control_fault += has(hazards, "control_path_fault") ? 1 : 0;
  }
  EXPECT_GT(large, worlds / 3);
  EXPECT_GT(null_controller, worlds / 4);
  EXPECT_GT(control_fault, worlds * 3 / 4);
}

TEST(ClientHazards, AClientWorldIsAPureFunctionOfItsSeedAndWritesBack) {
  for (std::uint64_t i = 0; i < 20; ++i) {
    const std::string first = scenario::write_scenario_yaml(client_world(i));
    EXPECT_EQ(scenario::write_scenario_yaml(client_world(i)), first) << "world " << i;
    // What world.yaml holds parses back to the same world.
    EXPECT_EQ(scenario::write_scenario_yaml(scenario::parse_scenario(first, "world.yaml")), first) << "world " << i;
  }
}

// The plugin that sent the user data goes on returning the pair to the end of the world: a
// locked source gone silent would leave the latency loop open for good (SPEC §4.3, no self-echo
// after a lock), and the oracle would fail the world's liveness whatever the client did.
TEST(ClientHazards, ThePluginGoesOnReturningThePairAfterItsUserData) {
  int episodes = 0;
  for (std::uint64_t i = 0; i < worlds; ++i) {
    const scenario::Scenario world = client_world(i);
    for (const scenario::TimelineEvent& event : world.timeline) {
      const auto* data = std::get_if<scenario::ClientDataAction>(&event.action);
      if (data == nullptr || !data->until) continue;
      ++episodes;
      const auto follows = std::find_if(world.timeline.begin(), world.timeline.end(), [&](const scenario::TimelineEvent& next) {
        const auto* after = std::get_if<scenario::ClientDataAction>(&next.action);
        return after != nullptr && next.at == *data->until && !after->until && after->source == data->source &&
               after->every == data->every;
      });
      ASSERT_NE(follows, world.timeline.end()) << "world " << i << ": nothing returns the pair after " << data->until->count() << " us";
      const auto& after = std::get<scenario::ClientDataAction>(follows->action);
      ASSERT_EQ(after.vehicles.size(), data->vehicles.size()) << "world " << i;
      for (const auto& [vehicle, entry] : after.vehicles) {
        EXPECT_EQ(entry.echo, scenario::ClientDataAction::Echo::latest) << "world " << i;
        EXPECT_FALSE(entry.user_data_json.has_value()) << "world " << i;
        EXPECT_FALSE(entry.disable_gamepad.value_or(false)) << "world " << i << ": the gamepad again";
      }
    }
  }
  EXPECT_GT(episodes, worlds / 2);
}

}  // namespace
}  // namespace ocp::campaign
