#pragma once
// The product's OCP settings (SPEC §9), given as `--plugin-param NAME VALUE` (repeatable),
// with the product's names and defaults:
//   tcp_port              vehicle-side TCP port                       4000
//   ocp_player_tcp_port   operator-side TCP port                      4001
//   ocp_tcp_allow_remote  bind 0.0.0.0 instead of 127.0.0.1; its mere presence enables it
//                         (the value is ignored, as in the product)   not set
//   latency_limit         HighLatency threshold, milliseconds         500
// Ports accept 0..65535 (0 = an ephemeral port, a simulator extension for tests);
// latency_limit accepts 1..3 600 000. Unknown names and bad values are errors naming the
// parameter and what was expected; the executables exit with code 2 on them.
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/time.hpp"

namespace ocp {

inline constexpr std::int64_t max_latency_limit_ms = 3'600'000;  // one hour

struct PluginParams {
  std::uint16_t tcp_port = 4000;
  std::uint16_t ocp_player_tcp_port = 4001;
  bool ocp_tcp_allow_remote = false;
  Millis latency_limit{500};
};

// The names above, in that order (for --help texts).
const std::vector<std::string_view>& plugin_param_names();

// Applies one NAME VALUE pair. On error `params` is unchanged.
[[nodiscard]] Status apply_plugin_param(PluginParams& params, std::string_view name,
                                        std::string_view value);

// Applies pairs in order onto the defaults; a later pair for the same name wins.
[[nodiscard]] Result<PluginParams> parse_plugin_params(
    const std::vector<std::pair<std::string, std::string>>& pairs);

}  // namespace ocp
