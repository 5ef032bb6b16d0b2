// The pieces of SPEC §10's cases (vehicle/10/*) that need no client: the gamepad frames their
// scripts are made of, and the case order that puts section 10 after section 3. The cases
// themselves run against real clients in suite_test.cpp: the reference client passes them
// (ConformanceSuite.ReferenceClientPassesEveryMustAndShouldCaseWithinAMinute), each
// broken_client.py safety mode fails its own (CoverageBrokenClient.GetsItsVerdict/vehicle_10_*),
// and a client without a safety report is not judged (ExampleClient.VehicleClientPassesTheVehicleSuite).
#include <gtest/gtest.h>

#include <algorithm>

#include "conformance/control_frames.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::conformance {
namespace {

TEST(SafetyFrames, APadFrameCarriesItsButtonsAndAxes) {
  CraftedControl control{AckPair{7, 8}};
  control.controller = CraftedController::pad;
  control.pad = CraftedPad{.start = true, .back = true, .left_x = -1.0, .left_trigger = 0.25, .right_trigger = 1.0};
  const auto decoded = decode_control_message(control_payload(control));
  ASSERT_TRUE(decoded.ok()) << decoded.error().message() << "\n" << control_payload(control);
  ASSERT_TRUE(decoded->controller.has_value());
  const Controller& pad = *decoded->controller;
  EXPECT_TRUE(pad.buttons.start);
  EXPECT_TRUE(pad.buttons.back);
  EXPECT_FALSE(pad.buttons.a);
  EXPECT_DOUBLE_EQ(pad.axes.left_x, -1.0);
  EXPECT_DOUBLE_EQ(pad.axes.left_trigger, 0.25);
  EXPECT_DOUBLE_EQ(pad.axes.right_trigger, 1.0);
  EXPECT_FALSE(pad.is_safe_default());
  control.pad = CraftedPad{};   // every field at rest: the Streamer's safe default
  EXPECT_TRUE(decode_control_message(control_payload(control))->controller->is_safe_default());
}

TEST(SafetyFrames, TheDrivingPresetIsUnchanged) {
  CraftedControl control{AckPair{7, 8}};
  const auto decoded = decode_control_message(control_payload(control));
  ASSERT_TRUE(decoded.ok()) << control_payload(control);
  EXPECT_TRUE(decoded->controller->buttons.a);
  EXPECT_DOUBLE_EQ(decoded->controller->axes.left_x, 0.25);
  EXPECT_DOUBLE_EQ(decoded->controller->axes.right_trigger, 0.5);
  EXPECT_DOUBLE_EQ(decoded->controller->axes.left_trigger, -1.0);
}

TEST(CaseOrder, SectionNumbersSortByValue) {
  EXPECT_TRUE(case_id_before("vehicle/3.3/4", "vehicle/10/1"));
  EXPECT_FALSE(case_id_before("vehicle/10/1", "vehicle/3.3/4"));
  EXPECT_TRUE(case_id_before("vehicle/2/7", "vehicle/3.1/1"));
  EXPECT_TRUE(case_id_before("vehicle/3.1/4", "vehicle/3.2/1"));
  EXPECT_TRUE(case_id_before("vehicle/10/2", "vehicle/10/10"));
  EXPECT_FALSE(case_id_before("vehicle/2/1", "vehicle/2/1"));
  EXPECT_TRUE(case_id_before("operator/2/1", "vehicle/2/1"));
  std::vector<std::string> ids;
  for (const VehicleCase& c : vehicle_cases()) ids.push_back(c.body.info.id);
  ASSERT_GE(ids.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(ids.end() - 4, ids.end()),
            (std::vector<std::string>{"vehicle/10/1", "vehicle/10/2", "vehicle/10/3", "vehicle/10/4"}));
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end(), case_id_before));
}

}  // namespace
}  // namespace ocp::conformance
