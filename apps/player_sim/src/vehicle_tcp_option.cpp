// Parsing of player_sim --vehicle-tcp NAME=PORT.
#include <algorithm>
#include <charconv>
#include <system_error>

#include "player_app/vehicle_tcp_option.hpp"

namespace ocp {
namespace {

Error usage(const std::string& text, const std::string& what) {
  return Error{std::make_error_code(std::errc::invalid_argument), "--vehicle-tcp '" + text + "': " + what};
}

}  // namespace

Result<std::map<std::string, std::uint16_t>> parse_vehicle_tcp(const std::vector<std::string>& texts,
                                                               const std::vector<std::string>& vehicles) {
  std::map<std::string, std::uint16_t> ports;
  for (const auto& text : texts) {
    const std::size_t equals = text.rfind('=');
    if (equals == std::string::npos) return usage(text, "expected NAME=PORT, e.g. truck-1=4000");
    const std::string name = text.substr(0, equals);
    const std::string port_text = text.substr(equals + 1);
    if (name.empty()) return usage(text, "the vehicle name is empty");
    if (std::find(vehicles.begin(), vehicles.end(), name) == vehicles.end()) {
      return usage(text, "unknown vehicle '" + name + "' (give it with --vehicle " + name + ")");
    }
    unsigned port = 0;
    const auto [end, error] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
    if (port_text.empty() || error != std::errc{} || end != port_text.data() + port_text.size() || port > 65535) {
      return usage(text, "expected a port number 0..65535, got '" + port_text + "'");
    }
    if (!ports.emplace(name, static_cast<std::uint16_t>(port)).second) {
      return usage(text, "vehicle '" + name + "' given twice");
    }
  }
  return ports;
}

}  // namespace ocp
