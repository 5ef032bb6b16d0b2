// The product's --plugin-param settings (SPEC §9): names, defaults, validation.
#include "sim_app/plugin_params.hpp"

#include <gtest/gtest.h>

namespace ocp {
namespace {

using Pairs = std::vector<std::pair<std::string, std::string>>;

TEST(PluginParams, DefaultsAreTheProductDefaults) {
  const auto params = parse_plugin_params({});
  ASSERT_TRUE(params.ok());
  EXPECT_EQ(params->tcp_port, 4000);
  EXPECT_EQ(params->ocp_player_tcp_port, 4001);
  EXPECT_FALSE(params->ocp_tcp_allow_remote);
  EXPECT_EQ(params->latency_limit, Millis{500});
}

TEST(PluginParams, EveryKnownNameIsApplied) {
  const auto params = parse_plugin_params(Pairs{{"tcp_port", "4100"},
                                                {"ocp_player_tcp_port", "4101"},
                                                {"ocp_tcp_allow_remote", "1"},
                                                {"latency_limit", "250"}});
  ASSERT_TRUE(params.ok()) << params.error().detail;
  EXPECT_EQ(params->tcp_port, 4100);
  EXPECT_EQ(params->ocp_player_tcp_port, 4101);
  EXPECT_TRUE(params->ocp_tcp_allow_remote);
  EXPECT_EQ(params->latency_limit, Millis{250});
}

TEST(PluginParams, AllowRemoteIsEnabledByPresenceWhateverTheValue) {
  for (const char* value : {"1", "0", "false", ""}) {
    const auto params = parse_plugin_params(Pairs{{"ocp_tcp_allow_remote", value}});
    ASSERT_TRUE(params.ok());
    EXPECT_TRUE(params->ocp_tcp_allow_remote) << "value '" << value << "'";
  }
}

TEST(PluginParams, LaterValueForTheSameNameWins) {
  const auto params = parse_plugin_params(Pairs{{"tcp_port", "4100"}, {"tcp_port", "4200"}});
  ASSERT_TRUE(params.ok());
  EXPECT_EQ(params->tcp_port, 4200);
}

TEST(PluginParams, PortZeroMeansEphemeralAndIsAccepted) {
  const auto params = parse_plugin_params(Pairs{{"tcp_port", "0"}, {"ocp_player_tcp_port", "65535"}});
  ASSERT_TRUE(params.ok());
  EXPECT_EQ(params->tcp_port, 0);
  EXPECT_EQ(params->ocp_player_tcp_port, 65535);
}

TEST(PluginParams, BadPortsAreRejectedWithTheParameterNamed) {
  for (const char* value : {"65536", "-1", "abc", "", "40 00", "4000x", "+4000", "4000.0"}) {
    const auto params = parse_plugin_params(Pairs{{"tcp_port", value}});
    ASSERT_FALSE(params.ok()) << "value '" << value << "'";
    EXPECT_EQ(params.error().code, std::errc::invalid_argument);
    EXPECT_EQ(params.error().detail, std::string("tcp_port: expected a port number 0..65535, got '") +
                                         value + "'");
  }
  EXPECT_FALSE(parse_plugin_params(Pairs{{"ocp_player_tcp_port", "70000"}}).ok());
}

TEST(PluginParams, BadLatencyLimitsAreRejected) {
  for (const char* value : {"0", "-5", "1.5", "fast", "3600001"}) {
    const auto params = parse_plugin_params(Pairs{{"latency_limit", value}});
    ASSERT_FALSE(params.ok()) << "value '" << value << "'";
    EXPECT_NE(params.error().detail.find("latency_limit: expected whole milliseconds"),
              std::string::npos);
  }
  EXPECT_TRUE(parse_plugin_params(Pairs{{"latency_limit", "3600000"}}).ok());
  EXPECT_TRUE(parse_plugin_params(Pairs{{"latency_limit", "1"}}).ok());
}

TEST(PluginParams, UnknownNameIsAnErrorListingTheKnownOnes) {
  const auto params = parse_plugin_params(Pairs{{"tcp_prot", "4000"}});
  ASSERT_FALSE(params.ok());
  EXPECT_EQ(params.error().detail,
            "unknown plugin parameter 'tcp_prot' (known: tcp_port, ocp_player_tcp_port, "
            "ocp_tcp_allow_remote, latency_limit)");
}

TEST(PluginParams, FailedApplyLeavesTheParametersUnchanged) {
  PluginParams params;
  params.tcp_port = 4100;
  EXPECT_FALSE(apply_plugin_param(params, "tcp_port", "nope").ok());
  EXPECT_EQ(params.tcp_port, 4100);
}

}  // namespace
}  // namespace ocp
