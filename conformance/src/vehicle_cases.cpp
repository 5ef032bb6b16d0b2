#include "conformance/vehicle_cases.hpp"

#include <algorithm>

namespace ocp::conformance {

std::vector<VehicleCase> vehicle_cases() {
  std::vector<VehicleCase> cases;
  add_framing_cases(cases);
  add_connection_cases(cases);
  add_message_cases(cases);
  add_echo_cases(cases);
  add_product_shape_cases(cases);
  add_safety_cases(cases);
  // Stable order by id (section, then number) whatever the files add.
  std::stable_sort(cases.begin(), cases.end(), [](const VehicleCase& a, const VehicleCase& b) {
    return case_id_before(a.body.info.id, b.body.info.id);
  });
  return cases;
}

}  // namespace ocp::conformance
