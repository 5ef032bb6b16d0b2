#pragma once
// The eleven faults of SPEC §6, in table order (which is also the fault_reason order).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ocp {

enum class FaultId : std::uint8_t {
  VehicleNoResponse,
  NoControlMessage,
  CameraLost,
  StreamerSlow,
  HighLatency,
  OperatorStationHasError,
  InvalidMac,
  ControlThreadChannelSlow,
  InputLost,
  NoFeedbackMessage,
  VehicleControlInactive,
};
inline constexpr std::size_t fault_count = 11;

enum class FaultSide { vehicle, operator_station };

std::string_view fault_identifier(FaultId id);  // "HighLatency"
std::string_view fault_display(FaultId id);     // "High Latency"
FaultSide fault_side(FaultId id);
// Faults that replace the controller with the default one (SPEC §3.2 Decision).
bool is_control_path_fault(FaultId id);
std::optional<FaultId> parse_fault_identifier(std::string_view identifier);

// A set of active faults; iteration is always in table order.
class FaultSet {
 public:
  void set(FaultId id, bool active);
  bool contains(FaultId id) const;
  bool empty() const { return bits_ == 0; }
  bool any_control_path() const;
  std::vector<FaultId> to_vector() const;
  std::vector<std::string> identifiers() const;  // for feedback sender_fault / receiver_fault
  // Display strings joined with ", " in table order; "" when empty (telemetry.fault_reason).
  std::string fault_reason() const;
  bool operator==(const FaultSet&) const = default;

 private:
  std::uint16_t bits_ = 0;
};

}  // namespace ocp
