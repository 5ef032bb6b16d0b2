// The send path of the reference vehicle client: one VehicleResponseMessage per control
// message (the echo) plus keep-alive responses when response_period passes without one.
// Everything the response needs is prepared ahead (user data is re-encoded at the model rate),
// so an echo is: copy the pair, encode into a reused buffer, frame, write. The client itself
// allocates nothing here in the steady state and never waits on the safety layer or the model.
#include <fmt/format.h>

#include <limits>

#include "ocp/json_codec.hpp"
#include "vehicle_client/user_data.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {
namespace {

// What a JSON library that stores every number as a double does to a u64 (the bug the
// ack-through-double switch reproduces): exact up to 2^53, rounded above it.
std::uint64_t through_double(std::uint64_t value) {
  const double rounded = static_cast<double>(value);
  // 2^64 - 1 rounds up to 2^64, which no u64 holds: saturate instead of overflowing.
  if (rounded >= 18446744073709551616.0) return std::numeric_limits<std::uint64_t>::max();
  return static_cast<std::uint64_t>(rounded);
}

}  // namespace

void VehicleClient::send_response(ResponseCause cause) {
  const Misbehaviour& misbehave = config_.misbehave;
  if (!stream_ || !echo_pair_ || misbehave.silent) return;
  const SimTime now = executor_.now();

  response_.ack = *echo_pair_;
  if (misbehave.ack_through_double) response_.ack.ack_time = through_double(response_.ack.ack_time);
  if (misbehave.corrupt_mac) response_.ack.ack_time_mac ^= corrupt_mac_mask;
  encode_vehicle_response(response_, payload_buffer_);

  frame_buffer_.clear();
  if (misbehave.bad_response != BadResponse::none) {
    write_bad_response(misbehave.bad_response);
    return;
  }
  if (misbehave.malformed_json) {
    payload_buffer_.resize(payload_buffer_.size() / 2);  // cut mid-object: not JSON any more
  }
  if (misbehave.oversized_frames) {
    // Deliberately past the limit: append_frame refuses, so only the header is the codec's.
    // Trailing whitespace keeps it valid JSON, so only the size is wrong.
    payload_buffer_.resize(std::max(payload_buffer_.size(), oversized_payload_bytes), ' ');
    append_length_prefix(static_cast<std::uint32_t>(payload_buffer_.size()), frame_buffer_);
    frame_buffer_ += payload_buffer_;
  } else if (const Status framed = append_frame(payload_buffer_, frame_buffer_); !framed.ok()) {
    // Cannot happen with bounded user data; refuse rather than send something invalid.
    logger_.error("response not sent: {}", framed.error().message());
    return;
  }

  ++stats_.responses_sent;
  ++(cause == ResponseCause::echo ? stats_.echo_responses_sent : stats_.keepalive_responses_sent);
  stats_.bytes_sent += frame_buffer_.size();
  stats_.largest_response_bytes = std::max(stats_.largest_response_bytes, payload_buffer_.size());
  last_response_time_ = now;

  if (misbehave.delay_responses.count() > 0) {
    const LivenessToken::Watch owner = liveness_.watch();
    const std::uint64_t id = connection_id_;
    executor_.call_after(misbehave.delay_responses, [this, owner, id, frame = frame_buffer_] {
      if (owner.alive() && id == connection_id_ && stream_) stream_->write(frame);
    });
  } else {
    stream_->write(frame_buffer_);
  }
  if (keepalive_timer_ == 0) arm_keepalive(now + config_.response_period);
}

// One response broken as `kind` says (misbehaviour.hpp), in place of the real one. Not counted
// as a response sent: the Streamer cannot take it for one.
void VehicleClient::write_bad_response(BadResponse kind) {
  const std::uint64_t ack_time = response_.ack.ack_time;
  const std::uint32_t mac = response_.ack.ack_time_mac;
  switch (kind) {
    case BadResponse::missing_field: payload_buffer_ = fmt::format(R"({{"ack_time":{}}})", ack_time); break;
    case BadResponse::wrong_type: payload_buffer_ = fmt::format(R"({{"ack_time":"{}","ack_time_mac":{}}})", ack_time, mac); break;
    case BadResponse::not_an_object: payload_buffer_ = fmt::format("[{},{}]", ack_time, mac); break;
    case BadResponse::ack_time_out_of_range:
      payload_buffer_ = fmt::format(R"({{"ack_time":18446744073709551616,"ack_time_mac":{}}})", mac);
      break;
    case BadResponse::eof_mid_frame:
    case BadResponse::none: break;   // the real payload, cut below
  }
  (void)append_frame(payload_buffer_, frame_buffer_);   // all of these are far below 16 KiB
  if (kind != BadResponse::eof_mid_frame) {
    stream_->write(frame_buffer_);
    return;
  }
  stream_->write(std::string_view(frame_buffer_).substr(0, frame_buffer_.size() / 2));
  close_with(DisconnectKind::misbehaved, "misbehave: hung up in the middle of a frame");
}

// The keep-alive tasks capture only `this` (std::function keeps that inline: no allocation
// per re-arm, which happens about once per response period): a pending keep-alive always
// belongs to the current connection, and release_connection() — also run by the destructor —
// cancels it.
void VehicleClient::arm_keepalive(SimTime deadline) {
  keepalive_timer_ =
      executor_.call_at_or_later(deadline, config_.keepalive_slack, [this] { on_keepalive(/*deferred=*/false); });
}

void VehicleClient::on_keepalive(bool deferred) {
  // Re-armed lazily from the last response instead of cancelled on every echo: at most one
  // timer event per period, and the gap between responses never exceeds response_period (in
  // real time, + keepalive_slack).
  keepalive_timer_ = 0;
  if (!stream_ || !last_response_time_) return;
  const SimTime due = *last_response_time_ + config_.response_period;
  if (due > executor_.now()) {
    arm_keepalive(due);
    return;
  }
  if (!deferred) {
    // Yield once: a control message due at this same instant runs first, and its echo makes
    // this keep-alive unnecessary (otherwise a 10 ms control stream would get two responses
    // per period). Still the same instant, so the gap bound holds.
    keepalive_timer_ = executor_.post([this] { on_keepalive(/*deferred=*/true); });
    return;
  }
  send_response(ResponseCause::keepalive);
}

void VehicleClient::refresh_user_data() {
  ++user_data_sequence_;
  if (!response_.vehicle_user_data) response_.vehicle_user_data.emplace();
  VehicleUserData& data = *response_.vehicle_user_data;
  data.pos = model_.state().geodetic;
  std::string& text = data.user_data.text;
  encode_user_data(UserDataSample{.vehicle = model_.state(),
                                  .safety = safety_.output(),
                                  .last_latency_ms = stats_.last_latency_ms,
                                  .sequence = user_data_sequence_,
                                  .timestamp = model_.time(),
                                  .misbehave = &config_.misbehave},
                   text);
  // The payload must stay far below 16 KiB whatever the model reports: check, never trust.
  if (text.size() > config_.user_data_limit_bytes) {
    logger_.error("user data of {} bytes exceeds the {} byte limit; sending a placeholder",
                  text.size(), config_.user_data_limit_bytes);
    text = fmt::format(R"({{"error":"user data too large","sequence":{}}})", user_data_sequence_);
  }
}

const std::string& VehicleClient::user_data_json() const {
  return response_.vehicle_user_data->user_data.text;
}

}  // namespace ocp
