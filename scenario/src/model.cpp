// Small pure helpers of the scenario model: applying and interpolating impairment settings.
#include "scenario/model.hpp"

#include <cmath>

namespace ocp::scenario {

Impairments apply_patch(Impairments base, const ImpairmentPatch& patch) {
  if (patch.delay) base.delay = *patch.delay;
  if (patch.jitter) base.jitter = *patch.jitter;
  if (patch.jitter_kind) base.jitter_kind = *patch.jitter_kind;
  // A jitter amount without a kind means uniform: "jitter: 5ms" should do something.
  if (patch.jitter && !patch.jitter_kind && base.jitter_kind == Impairments::JitterKind::none) {
    base.jitter_kind = Impairments::JitterKind::uniform;
  }
  if (patch.reorder_extra_delay) base.reorder_extra_delay = *patch.reorder_extra_delay;
  if (patch.loss) base.loss_probability = *patch.loss;
  if (patch.duplicate) base.duplicate_probability = *patch.duplicate;
  if (patch.reorder) base.reorder_probability = *patch.reorder;
  if (patch.bandwidth_bps) base.bandwidth_bits_per_second = *patch.bandwidth_bps;
  if (patch.burst_loss) base.burst_loss = *patch.burst_loss;
  if (patch.good_to_bad) base.good_to_bad_probability = *patch.good_to_bad;
  if (patch.bad_to_good) base.bad_to_good_probability = *patch.bad_to_good;
  if (patch.loss_in_good) base.loss_in_good = *patch.loss_in_good;
  if (patch.loss_in_bad) base.loss_in_bad = *patch.loss_in_bad;
  if (patch.down) base.down = *patch.down;
  if (patch.queue_limit_bytes) base.queue_limit_bytes = *patch.queue_limit_bytes;
  if (patch.queue_limit_packets) base.queue_limit_packets = *patch.queue_limit_packets;
  if (patch.trace) base.trace = *patch.trace;
  if (patch.replay) base.replay = *patch.replay;
  return base;
}

namespace {
double mix(double a, double b, double f) { return a + (b - a) * f; }
Micros mix(Micros a, Micros b, double f) {
  return Micros{static_cast<std::int64_t>(std::llround(mix(static_cast<double>(a.count()),
                                                           static_cast<double>(b.count()), f)))};
}
}  // namespace

Impairments interpolate(const Impairments& from, const Impairments& to, double fraction) {
  Impairments out = to;
  out.delay = mix(from.delay, to.delay, fraction);
  out.jitter = mix(from.jitter, to.jitter, fraction);
  out.reorder_extra_delay = mix(from.reorder_extra_delay, to.reorder_extra_delay, fraction);
  out.loss_probability = mix(from.loss_probability, to.loss_probability, fraction);
  out.duplicate_probability = mix(from.duplicate_probability, to.duplicate_probability, fraction);
  out.reorder_probability = mix(from.reorder_probability, to.reorder_probability, fraction);
  out.good_to_bad_probability = mix(from.good_to_bad_probability, to.good_to_bad_probability, fraction);
  out.bad_to_good_probability = mix(from.bad_to_good_probability, to.bad_to_good_probability, fraction);
  out.loss_in_good = mix(from.loss_in_good, to.loss_in_good, fraction);
  out.loss_in_bad = mix(from.loss_in_bad, to.loss_in_bad, fraction);
  // 0 means unlimited, so a ramp from or to 0 bandwidth is a step, not a slide through 0.
  if (from.bandwidth_bits_per_second > 0 && to.bandwidth_bits_per_second > 0) {
    out.bandwidth_bits_per_second =
        mix(from.bandwidth_bits_per_second, to.bandwidth_bits_per_second, fraction);
  }
  return out;
}

std::string_view notable_kind_name(NotableKind kind) {
  switch (kind) {
    case NotableKind::source_locked: return "source_locked";
    case NotableKind::source_conflict: return "source_conflict";
    case NotableKind::connection_closed: return "connection_closed";
    case NotableKind::connection_refused: return "connection_refused";
  }
  return "?";
}

std::string_view bad_client_message_name(BadClientMessage kind) {
  switch (kind) {
    case BadClientMessage::none: return "none";
    case BadClientMessage::not_an_object: return "not_an_object";
    case BadClientMessage::wrong_type: return "wrong_type";
    case BadClientMessage::eof_mid_frame: return "eof_mid_frame";
  }
  return "?";
}

std::string_view invariant_name(Invariant invariant) {
  switch (invariant) {
    case Invariant::default_controller_during_control_fault:
      return "default_controller_during_control_fault";
    case Invariant::no_stale_pair_after_reconnect: return "no_stale_pair_after_reconnect";
  }
  return "?";
}

std::string_view direction_name(Direction direction) {
  switch (direction) {
    case Direction::both: return "both";
    case Direction::to_streamer: return "to_streamer";
    case Direction::to_player: return "to_player";
  }
  return "?";
}

}  // namespace ocp::scenario
