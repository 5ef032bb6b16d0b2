#include "ocp/faults.hpp"

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

struct FaultInfo {
  std::string_view identifier;
  std::string_view display;
  FaultSide side;
  bool control_path;
};

// SPEC §6, in table order. Control-path membership is the SPEC §3.2 Decision: CameraLost
// and StreamerSlow set telemetry.fault but pass the controller through.
constexpr std::array<FaultInfo, fault_count> fault_table{{
    {"VehicleNoResponse", "Vehicle No Response", FaultSide::vehicle, false},
    {"NoControlMessage", "No Control Message", FaultSide::vehicle, true},
    {"CameraLost", "Camera Lost", FaultSide::vehicle, false},
    {"StreamerSlow", "Streamer Slow", FaultSide::vehicle, false},
    {"HighLatency", "High Latency", FaultSide::vehicle, true},
    {"OperatorStationHasError", "Operator Station Has Error", FaultSide::vehicle, true},
    {"InvalidMac", "Latency Loop Not Closed", FaultSide::vehicle, true},
    {"ControlThreadChannelSlow", "Control Thread Channel Slow", FaultSide::vehicle, true},
    {"InputLost", "Input Lost", FaultSide::operator_station, false},
    {"NoFeedbackMessage", "No Feedback Message", FaultSide::operator_station, false},
    {"VehicleControlInactive", "Vehicle Control Inactive", FaultSide::operator_station, false},
}};

const FaultInfo& info(FaultId id) { return fault_table[static_cast<std::size_t>(id)]; }
std::uint16_t bit(FaultId id) { return static_cast<std::uint16_t>(1u << static_cast<unsigned>(id)); }

}  // namespace

std::string_view fault_identifier(FaultId id) { return info(id).identifier; }
std::string_view fault_display(FaultId id) { return info(id).display; }
FaultSide fault_side(FaultId id) { return info(id).side; }
bool is_control_path_fault(FaultId id) { return info(id).control_path; }

std::optional<FaultId> parse_fault_identifier(std::string_view identifier) {
  for (std::size_t i = 0; i < fault_count; ++i) {
    if (fault_table[i].identifier == identifier) return static_cast<FaultId>(i);
  }
  return std::nullopt;
}

void FaultSet::set(FaultId id, bool active) {
  if (active) {
    bits_ |= bit(id);
  } else {
    bits_ &= static_cast<std::uint16_t>(~bit(id));
  }
  OCP_INVARIANT(contains(id) == active, "a fault is in the set exactly when it was last set active");
  OCP_INVARIANT(bits_ < (1u << fault_count), "a fault set holds only faults of the table");
}

bool FaultSet::contains(FaultId id) const { return (bits_ & bit(id)) != 0; }

bool FaultSet::any_control_path() const {
  for (std::size_t i = 0; i < fault_count; ++i) {
    const auto id = static_cast<FaultId>(i);
    if (contains(id) && is_control_path_fault(id)) return true;
  }
  return false;
}

std::vector<FaultId> FaultSet::to_vector() const {
  std::vector<FaultId> result;
  for (std::size_t i = 0; i < fault_count; ++i) {
    const auto id = static_cast<FaultId>(i);
    if (contains(id)) result.push_back(id);
  }
  return result;
}

std::vector<std::string> FaultSet::identifiers() const {
  std::vector<std::string> result;
  for (FaultId id : to_vector()) result.emplace_back(fault_identifier(id));
  return result;
}

std::string FaultSet::fault_reason() const {
  std::string result;
  for (FaultId id : to_vector()) {
    if (!result.empty()) result += ", ";
    result += fault_display(id);
  }
  return result;
}

}  // namespace ocp
