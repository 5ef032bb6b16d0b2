#pragma once
// player_sim --vehicle-tcp NAME=PORT (repeatable): that simulated vehicle gets a real
// vehicle-side TCP API (the Streamer's front, SPEC §3.1) on PORT instead of the in-process
// reference vehicle client, so an external vehicle integration shares the simulated link
// with operator-side clients and web view pages.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ocp/error.hpp"

namespace ocp {

// Checks every text against the simulated vehicle names: "truck-1=4000" → {truck-1: 4000}.
// PORT is 0..65535 (0 = a free port, logged). Errors name the option and what is wrong: no
// '=', empty name, a vehicle not given with --vehicle, a vehicle given twice, a bad port.
[[nodiscard]] Result<std::map<std::string, std::uint16_t>> parse_vehicle_tcp(
    const std::vector<std::string>& texts, const std::vector<std::string>& vehicles);

}  // namespace ocp
