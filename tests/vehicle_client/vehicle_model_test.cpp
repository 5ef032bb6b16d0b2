// The Eigen kinematic bicycle: distances, turn radius, stopping, and the lat/lon mapping.
#include "vehicle_client/vehicle_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ocp {
namespace {

constexpr Micros step_10ms{10'000};
constexpr Position gothenburg{57.7089, 11.9746};

VehicleParams no_rolling_loss() {
  VehicleParams params;
  params.rolling_decel_mps2 = 0.0;
  return params;
}

TEST(VehicleModel, ConstantAccelerationCoversHalfATSquared) {
  VehicleParams params = no_rolling_loss();
  params.max_accel_mps2 = 2.0;
  KinematicBicycle model(params, gothenburg, /*heading=*/90.0);  // east
  for (int step = 0; step < 300; ++step) model.step({1.0, 0.0, 0.0}, step_10ms);  // 3 s
  EXPECT_NEAR(model.state().speed_mps, 6.0, 1e-9);
  EXPECT_NEAR(model.state().odometer_m, 9.0, 1e-9);
  EXPECT_NEAR(model.state().position_m.x(), 9.0, 1e-9);
  EXPECT_NEAR(model.state().position_m.y(), 0.0, 1e-9);
}

TEST(VehicleModel, DrivesStraightAlongItsHeading) {
  VehicleParams params = no_rolling_loss();
  params.max_accel_mps2 = 1.0;
  KinematicBicycle model(params, gothenburg, /*heading=*/0.0);  // north
  for (int step = 0; step < 200; ++step) model.step({1.0, 0.0, 0.0}, step_10ms);
  EXPECT_NEAR(model.state().position_m.x(), 0.0, 1e-9);
  EXPECT_NEAR(model.state().position_m.y(), 2.0, 1e-9);
  EXPECT_NEAR(model.state().heading_deg(), 0.0, 1e-9);
}

TEST(VehicleModel, ConstantSteeringTracesACircleOfRadiusWheelbaseOverTanSteer) {
  VehicleParams params = no_rolling_loss();
  params.wheelbase_m = 2.7;
  params.max_steer_rad = 0.4;
  params.max_accel_mps2 = 1.0;
  params.max_speed_mps = 5.0;
  KinematicBicycle model(params, gothenburg, /*heading=*/90.0);
  const double expected_radius_m = params.wheelbase_m / std::tan(0.4 * 0.5);
  // Left turn from heading east: the centre is straight north of the start, one radius away.
  const Eigen::Vector2d centre{0.0, expected_radius_m};
  for (int step = 0; step < 3000; ++step) {
    model.step({step < 500 ? 1.0 : 0.0, 0.0, 0.5}, step_10ms);  // accelerate, then coast
    ASSERT_NEAR((model.state().position_m - centre).norm(), expected_radius_m, 1e-9) << "step " << step;
  }
  EXPECT_GT(model.state().odometer_m, 2.0 * std::numbers::pi * expected_radius_m);  // went round
}

TEST(VehicleModel, FullBrakeStopsWithinVSquaredOverTwoA) {
  VehicleParams params;
  params.max_accel_mps2 = 2.0;
  params.max_brake_mps2 = 7.0;
  params.rolling_decel_mps2 = 0.1;
  params.max_speed_mps = 50.0;
  KinematicBicycle model(params, gothenburg);
  while (model.state().speed_mps < 10.0) model.step({1.0, 0.0, 0.0}, Micros{1'000});
  const double speed = model.state().speed_mps;
  const double start_odometer = model.state().odometer_m;
  for (int step = 0; step < 300; ++step) model.step({0.0, 1.0, 0.0}, step_10ms);
  EXPECT_EQ(model.state().speed_mps, 0.0);
  EXPECT_NEAR(model.state().odometer_m - start_odometer, speed * speed / (2.0 * 7.1), 1e-9);
}

TEST(VehicleModel, NeverReversesAndRespectsTopSpeed) {
  VehicleParams params;
  params.max_speed_mps = 3.0;
  KinematicBicycle model(params, gothenburg);
  for (int step = 0; step < 100; ++step) model.step({0.0, 1.0, 0.0}, step_10ms);
  EXPECT_EQ(model.state().speed_mps, 0.0);
  EXPECT_EQ(model.state().odometer_m, 0.0);
  for (int step = 0; step < 1000; ++step) model.step({1.0, 0.0, 0.0}, step_10ms);
  EXPECT_EQ(model.state().speed_mps, 3.0);
}

TEST(VehicleModel, ReportsLatLonOfTheLocalPosition) {
  VehicleParams params = no_rolling_loss();
  params.max_accel_mps2 = 2.0;
  params.max_speed_mps = 50.0;
  KinematicBicycle model(params, gothenburg, /*heading=*/0.0);
  for (int step = 0; step < 1000; ++step) model.step({1.0, 0.0, 0.0}, step_10ms);  // 100 m north
  EXPECT_NEAR(model.state().position_m.y(), 100.0, 1e-6);
  // One degree of latitude is ~111.3 km at 57.7°N.
  EXPECT_NEAR(model.state().geodetic.lat - gothenburg.lat, 100.0 / 111'330.0, 2e-6);
  EXPECT_DOUBLE_EQ(model.state().geodetic.lon, gothenburg.lon);
}

TEST(VehicleModel, TangentPlaneRoundTrips) {
  const LocalTangentPlane plane(gothenburg);
  const Eigen::Vector2d local{1234.5, -678.9};
  const Eigen::Vector2d back = plane.to_local(plane.to_geodetic(local));
  EXPECT_NEAR((back - local).norm(), 0.0, 1e-6);
  // A degree of longitude shrinks with cos(latitude).
  const double east_per_degree = plane.to_local(Position{gothenburg.lat, gothenburg.lon + 1.0}).x();
  EXPECT_NEAR(east_per_degree, 111'320.0 * std::cos(57.7089 * std::numbers::pi / 180.0), 300.0);
}

TEST(VehicleModel, AdvanceToTakesWholeFixedSteps) {
  KinematicBicycle model(VehicleParams{}, gothenburg);
  model.reset_time(Micros{0});
  EXPECT_EQ(model.advance_to(Micros{35'000}, {}, step_10ms), 3);
  EXPECT_EQ(model.time(), Micros{30'000});
  EXPECT_EQ(model.advance_to(Micros{39'999}, {}, step_10ms), 0);
  EXPECT_EQ(model.advance_to(Micros{40'000}, {}, step_10ms), 1);
}

TEST(VehicleModel, HeadingIsACompassBearing) {
  EXPECT_NEAR(KinematicBicycle(VehicleParams{}, gothenburg, 0.0).state().heading_deg(), 0.0, 1e-9);
  EXPECT_NEAR(KinematicBicycle(VehicleParams{}, gothenburg, 90.0).state().heading_deg(), 90.0, 1e-9);
  EXPECT_NEAR(KinematicBicycle(VehicleParams{}, gothenburg, 270.0).state().heading_deg(), 270.0, 1e-9);
}

TEST(VehicleModel, RejectsUnusableParameters) {
  EXPECT_FALSE(validate(VehicleParams{}));
  VehicleParams params;
  params.wheelbase_m = 0.0;
  EXPECT_TRUE(validate(params));
  params = {};
  params.max_steer_rad = 2.0;
  EXPECT_TRUE(validate(params));
}

}  // namespace
}  // namespace ocp
