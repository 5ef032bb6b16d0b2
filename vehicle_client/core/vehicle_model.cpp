#include "vehicle_client/vehicle_model.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

// WGS84 ellipsoid.
constexpr double semi_major_axis_m = 6378137.0;
constexpr double eccentricity_squared = 6.69437999014e-3;

constexpr double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }
constexpr double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

double clamp_finite(double value, double low, double high) {
  return std::isfinite(value) ? std::clamp(value, low, high) : 0.0;
}

}  // namespace

std::optional<std::string> validate(const VehicleParams& params) {
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  if (!positive(params.wheelbase_m)) return "wheelbase must be positive";
  if (!positive(params.max_steer_rad) || params.max_steer_rad >= std::numbers::pi / 2) {
    return "max steering angle must be in (0, pi/2) rad";
  }
  if (!positive(params.max_accel_mps2)) return "max acceleration must be positive";
  if (!positive(params.max_brake_mps2)) return "max braking deceleration must be positive";
  if (!std::isfinite(params.rolling_decel_mps2) || params.rolling_decel_mps2 < 0.0) {
    return "rolling deceleration must be >= 0";
  }
  if (!positive(params.max_speed_mps)) return "max speed must be positive";
  return std::nullopt;
}

double VehicleState::heading_deg() const {
  // Compass heading is clockwise from north; yaw is counter-clockwise from east.
  double heading = 90.0 - degrees(yaw_rad);
  heading = std::fmod(heading, 360.0);
  if (heading < 0.0) heading += 360.0;
  return heading;
}

LocalTangentPlane::LocalTangentPlane(Position origin) : origin_(origin) {
  const double sin_lat = std::sin(radians(origin.lat));
  const double denominator = 1.0 - eccentricity_squared * sin_lat * sin_lat;
  const double meridional_radius_m =
      semi_major_axis_m * (1.0 - eccentricity_squared) / (denominator * std::sqrt(denominator));
  const double prime_vertical_radius_m = semi_major_axis_m / std::sqrt(denominator);
  metres_per_radian_north_ = meridional_radius_m;
  metres_per_radian_east_ = prime_vertical_radius_m * std::cos(radians(origin.lat));
}

Position LocalTangentPlane::to_geodetic(const Eigen::Vector2d& east_north_m) const {
  return Position{origin_.lat + degrees(east_north_m.y() / metres_per_radian_north_),
                  origin_.lon + degrees(east_north_m.x() / metres_per_radian_east_)};
}

Eigen::Vector2d LocalTangentPlane::to_local(const Position& point) const {
  return {radians(point.lon - origin_.lon) * metres_per_radian_east_,
          radians(point.lat - origin_.lat) * metres_per_radian_north_};
}

KinematicBicycle::KinematicBicycle(VehicleParams params, Position start, double start_heading_deg)
    : params_(params), plane_(start) {
  state_.yaw_rad = radians(90.0 - start_heading_deg);
  state_.geodetic = start;
}

void KinematicBicycle::step(const ActuatorCommand& command, Micros dt) {
  const double dt_s = std::chrono::duration<double>(dt).count();
  time_ += dt;
  if (dt_s <= 0.0) return;

  const double throttle = clamp_finite(command.throttle, 0.0, 1.0);
  const double brake = clamp_finite(command.brake, 0.0, 1.0);
  state_.steer_rad = clamp_finite(command.steer, -1.0, 1.0) * params_.max_steer_rad;

  // Longitudinal: constant acceleration over the step; no reverse gear, speed stops at 0.
  const double v0 = state_.speed_mps;
  double accel = throttle * params_.max_accel_mps2 - brake * params_.max_brake_mps2;
  if (v0 > 0.0 || accel > 0.0) accel -= params_.rolling_decel_mps2;
  double distance_m = 0.0;
  double v1 = v0 + accel * dt_s;
  if (v1 <= 0.0) {
    // Stops inside this step: distance to standstill is v0² / (2·|a|).
    distance_m = accel < 0.0 ? v0 * v0 / (2.0 * -accel) : 0.0;
    v1 = 0.0;
  } else if (v1 > params_.max_speed_mps) {
    v1 = params_.max_speed_mps;
    distance_m = (v0 + v1) / 2.0 * dt_s;  // speed cap: close enough within one step
  } else {
    distance_m = (v0 + v1) / 2.0 * dt_s;
  }
  state_.speed_mps = v1;
  state_.odometer_m += distance_m;

  // Lateral: the path over the step is an arc of curvature tan(δ) / L (exact for this model).
  const double curvature_per_m = std::tan(state_.steer_rad) / params_.wheelbase_m;
  const double yaw_change_rad = curvature_per_m * distance_m;
  Eigen::Vector2d displacement_m;
  if (std::abs(yaw_change_rad) < 1e-12) {
    displacement_m = {distance_m, 0.0};
  } else {
    const double radius_m = 1.0 / curvature_per_m;
    displacement_m = {radius_m * std::sin(yaw_change_rad), radius_m * (1.0 - std::cos(yaw_change_rad))};
  }
  state_.position_m += Eigen::Rotation2Dd(state_.yaw_rad) * displacement_m;
  state_.yaw_rad = std::remainder(state_.yaw_rad + yaw_change_rad, 2.0 * std::numbers::pi);
  state_.geodetic = plane_.to_geodetic(state_.position_m);
  OCP_INVARIANT(state_.speed_mps >= 0.0 && state_.speed_mps <= params_.max_speed_mps, "speed stays in [0, max_speed]: no reverse gear");
  OCP_INVARIANT(distance_m >= 0.0, "the odometer never runs backwards");
}

int KinematicBicycle::advance_to(SimTime now, const ActuatorCommand& command, Micros step_size) {
  int steps = 0;
  if (step_size.count() <= 0) return steps;
  while (time_ + step_size <= now) {
    step(command, step_size);
    ++steps;
  }
  return steps;
}

}  // namespace ocp
