#pragma once
// Kinematic bicycle model (rear-axle reference point) on a local tangent plane, with Eigen:
//   ẋ = v·cos ψ,  ẏ = v·sin ψ,  ψ̇ = v·tan δ / L,  v̇ = a(throttle, brake)
// integrated at a fixed step. Within a step speed changes linearly and the path is the exact
// arc of the constant-curvature motion, so a constant steering angle traces a circle of
// radius L / tan δ to machine precision. Position is reported as lat/lon around a start point.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "ocp/messages.hpp"
#include "ocp/time.hpp"
#include "vehicle_client/safety_layer.hpp"

namespace ocp {

struct VehicleParams {
  double wheelbase_m = 2.7;
  double max_steer_rad = 0.55;     // road-wheel angle at steer = ±1
  double max_accel_mps2 = 2.5;     // at throttle = 1
  double max_brake_mps2 = 7.0;     // at brake = 1
  double rolling_decel_mps2 = 0.1; // coasting deceleration (no reverse: speed stops at 0)
  double max_speed_mps = 15.0;
};
std::optional<std::string> validate(const VehicleParams& params);

struct VehicleState {
  Eigen::Vector2d position_m{0.0, 0.0};  // east, north from the start point
  double yaw_rad = 0.0;                  // math convention: 0 = east, counter-clockwise
  double speed_mps = 0.0;
  double steer_rad = 0.0;
  double odometer_m = 0.0;
  Position geodetic;                     // lat/lon of position_m
  double heading_deg() const;            // compass: 0 = north, 90 = east, in [0, 360)
};

// Local tangent plane (east/north metres) ↔ WGS84 lat/lon around an origin. Uses the
// ellipsoid's radii of curvature at the origin: accurate to centimetres within a few km.
class LocalTangentPlane {
 public:
  explicit LocalTangentPlane(Position origin);
  Position to_geodetic(const Eigen::Vector2d& east_north_m) const;
  Eigen::Vector2d to_local(const Position& point) const;
  const Position& origin() const { return origin_; }

 private:
  Position origin_;
  double metres_per_radian_north_;
  double metres_per_radian_east_;
};

class KinematicBicycle {
 public:
  // `start_heading_deg` is a compass heading (0 = north).
  KinematicBicycle(VehicleParams params, Position start, double start_heading_deg = 0.0);

  // Advances by `dt` under `command` (clamped to its valid ranges).
  void step(const ActuatorCommand& command, Micros dt);
  // Advances to `now` in fixed steps of `step_size`, holding `command`; returns steps taken.
  int advance_to(SimTime now, const ActuatorCommand& command, Micros step_size);

  const VehicleState& state() const { return state_; }
  const VehicleParams& params() const { return params_; }
  SimTime time() const { return time_; }
  void reset_time(SimTime now) { time_ = now; }

 private:
  VehicleParams params_;
  LocalTangentPlane plane_;
  VehicleState state_;
  SimTime time_{0};
};

}  // namespace ocp
