#include "sim_app/plugin_params.hpp"

#include <charconv>
#include <limits>
#include <optional>

namespace ocp {

namespace {

Error invalid(std::string detail) {
  return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
}

// A whole decimal integer, nothing else ("+5", " 5", "5x", "5.0" and "" are rejected).
std::optional<std::int64_t> parse_integer(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::int64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [rest, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || rest != end) return std::nullopt;
  return value;
}

Status parse_port(std::string_view name, std::string_view value, std::uint16_t& port) {
  const auto number = parse_integer(value);
  if (!number || *number < 0 || *number > std::numeric_limits<std::uint16_t>::max()) {
    return invalid(std::string(name) + ": expected a port number 0..65535, got '" +
                   std::string(value) + "'");
  }
  port = static_cast<std::uint16_t>(*number);
  return Ok{};
}

}  // namespace

const std::vector<std::string_view>& plugin_param_names() {
  static const std::vector<std::string_view> names{"tcp_port", "ocp_player_tcp_port",
                                                   "ocp_tcp_allow_remote", "latency_limit"};
  return names;
}

Status apply_plugin_param(PluginParams& params, std::string_view name, std::string_view value) {
  if (name == "tcp_port") return parse_port(name, value, params.tcp_port);
  if (name == "ocp_player_tcp_port") return parse_port(name, value, params.ocp_player_tcp_port);
  if (name == "ocp_tcp_allow_remote") {
    // The product treats the parameter's presence as "on"; any value (even "0") enables it.
    params.ocp_tcp_allow_remote = true;
    return Ok{};
  }
  if (name == "latency_limit") {
    const auto number = parse_integer(value);
    if (!number || *number < 1 || *number > max_latency_limit_ms) {
      return invalid("latency_limit: expected whole milliseconds 1.." +
                     std::to_string(max_latency_limit_ms) + ", got '" + std::string(value) + "'");
    }
    params.latency_limit = Millis{*number};
    return Ok{};
  }
  std::string known;
  for (const auto known_name : plugin_param_names()) {
    known += known.empty() ? "" : ", ";
    known += known_name;
  }
  return invalid("unknown plugin parameter '" + std::string(name) + "' (known: " + known + ")");
}

Result<PluginParams> parse_plugin_params(
    const std::vector<std::pair<std::string, std::string>>& pairs) {
  PluginParams params;
  for (const auto& [name, value] : pairs) {
    if (auto status = apply_plugin_param(params, name, value); !status) return status.error();
  }
  return params;
}

}  // namespace ocp
