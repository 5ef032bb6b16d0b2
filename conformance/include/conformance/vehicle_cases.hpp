#pragma once
// The vehicle-side suite (`ocp_conformance vehicle`): every case, in a stable order.
#include <string>
#include <vector>

#include "conformance/case.hpp"
#include "conformance/streamer_host.hpp"

namespace ocp::conformance {

struct VehicleCase {
  Case body;
  StreamerSetup setup;  // how the Streamer is started for this case
};

std::vector<VehicleCase> vehicle_cases();
// The cases' order: by id, numbers by value ("vehicle/3.3/1" before "vehicle/10/1").
bool case_id_before(const std::string& a, const std::string& b);
// `ocp_conformance operator`: the Player's :4001 API (SPEC §4.2), same runner and reports.
std::vector<VehicleCase> operator_cases();

// By concern (one file each), concatenated by vehicle_cases().
void add_echo_cases(std::vector<VehicleCase>& cases);
void add_framing_cases(std::vector<VehicleCase>& cases);
void add_message_cases(std::vector<VehicleCase>& cases);
void add_connection_cases(std::vector<VehicleCase>& cases);
void add_product_shape_cases(std::vector<VehicleCase>& cases);
void add_safety_cases(std::vector<VehicleCase>& cases);
// By concern, concatenated by operator_cases().
void add_operator_framing_cases(std::vector<VehicleCase>& cases);
void add_operator_connection_cases(std::vector<VehicleCase>& cases);
void add_operator_data_cases(std::vector<VehicleCase>& cases);
void add_operator_product_shape_cases(std::vector<VehicleCase>& cases);

}  // namespace ocp::conformance
