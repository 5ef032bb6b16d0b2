#include <gtest/gtest.h>

#include "ocp/faults.hpp"

namespace ocp {
namespace {

TEST(Faults, EveryIdentifierRoundTripsThroughItsName) {
  for (std::size_t i = 0; i < fault_count; ++i) {
    const auto id = static_cast<FaultId>(i);
    EXPECT_EQ(parse_fault_identifier(fault_identifier(id)), id);
  }
  EXPECT_FALSE(parse_fault_identifier("High Latency").has_value());
}

TEST(Faults, DisplayStringsMatchTheSpecTable) {
  EXPECT_EQ(fault_display(FaultId::VehicleNoResponse), "Vehicle No Response");
  EXPECT_EQ(fault_display(FaultId::NoControlMessage), "No Control Message");
  EXPECT_EQ(fault_display(FaultId::CameraLost), "Camera Lost");
  EXPECT_EQ(fault_display(FaultId::StreamerSlow), "Streamer Slow");
  EXPECT_EQ(fault_display(FaultId::HighLatency), "High Latency");
  EXPECT_EQ(fault_display(FaultId::OperatorStationHasError), "Operator Station Has Error");
  EXPECT_EQ(fault_display(FaultId::InvalidMac), "Latency Loop Not Closed");
  EXPECT_EQ(fault_display(FaultId::ControlThreadChannelSlow), "Control Thread Channel Slow");
  EXPECT_EQ(fault_display(FaultId::InputLost), "Input Lost");
  EXPECT_EQ(fault_display(FaultId::NoFeedbackMessage), "No Feedback Message");
  EXPECT_EQ(fault_display(FaultId::VehicleControlInactive), "Vehicle Control Inactive");
}

TEST(Faults, SidesFollowTheSpecTable) {
  EXPECT_EQ(fault_side(FaultId::ControlThreadChannelSlow), FaultSide::vehicle);
  EXPECT_EQ(fault_side(FaultId::InputLost), FaultSide::operator_station);
  EXPECT_EQ(fault_side(FaultId::NoFeedbackMessage), FaultSide::operator_station);
  EXPECT_EQ(fault_side(FaultId::VehicleControlInactive), FaultSide::operator_station);
}

TEST(Faults, CameraLostAndStreamerSlowAreNotControlPathFaults) {
  EXPECT_FALSE(is_control_path_fault(FaultId::CameraLost));
  EXPECT_FALSE(is_control_path_fault(FaultId::StreamerSlow));
  for (FaultId id : {FaultId::NoControlMessage, FaultId::HighLatency, FaultId::InvalidMac,
                     FaultId::OperatorStationHasError, FaultId::ControlThreadChannelSlow}) {
    EXPECT_TRUE(is_control_path_fault(id)) << fault_identifier(id);
  }
}

TEST(FaultSet, FaultReasonJoinsDisplayStringsInTableOrder) {
  FaultSet faults;
  EXPECT_EQ(faults.fault_reason(), "");
  faults.set(FaultId::InvalidMac, true);
  faults.set(FaultId::HighLatency, true);
  faults.set(FaultId::NoControlMessage, true);
  EXPECT_EQ(faults.fault_reason(), "No Control Message, High Latency, Latency Loop Not Closed");
  EXPECT_EQ(faults.identifiers(),
            (std::vector<std::string>{"NoControlMessage", "HighLatency", "InvalidMac"}));
  faults.set(FaultId::HighLatency, false);
  EXPECT_EQ(faults.fault_reason(), "No Control Message, Latency Loop Not Closed");
}

TEST(FaultSet, AnyControlPathIgnoresCameraLostAndStreamerSlow) {
  FaultSet faults;
  faults.set(FaultId::CameraLost, true);
  faults.set(FaultId::StreamerSlow, true);
  EXPECT_FALSE(faults.any_control_path());
  EXPECT_FALSE(faults.empty());
  faults.set(FaultId::NoControlMessage, true);
  EXPECT_TRUE(faults.any_control_path());
}

}  // namespace
}  // namespace ocp
