#include "ocp/com_channel.hpp"

#include "ocp/invariant.hpp"
#include "ocp/mutants.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ocp {
namespace {

// SplitMix64: derives well-separated seeds for the two directions from one link seed.
std::uint64_t mix_seed(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ULL;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
  return value ^ (value >> 31);
}

constexpr double micros_per_second = 1e6;
constexpr double bits_per_byte = 8.0;

}  // namespace

LinkDirection::LinkDirection(Executor& executor, std::uint64_t seed) : executor_(executor), random_(seed) {}

LinkDirection::~LinkDirection() {
  for (const InFlight& flight : in_flight_) {
    if (flight.timer != 0) executor_.cancel(flight.timer);
  }
}

void LinkDirection::set_receiver(Receiver receiver) { receiver_ = std::move(receiver); }

void LinkDirection::set_identity(std::string_view name, LinkRoute route) {
  name_ = name;
  route_ = route;
}

void LinkDirection::set_impairments(const Impairments& impairments) {
  // A new trace starts now with an empty queue; other changes leave a running trace alone.
  if (impairments.trace != trace_queue_.trace_shared()) trace_queue_.reset(impairments.trace, executor_.now());
  // A new recording replays from its first message.
  if (impairments.replay != impairments_.replay) replay_next_ = 0;
  impairments_ = impairments;
  OCP_INVARIANT(impairments_.trace == trace_queue_.trace_shared(), "the trace queue runs the trace the impairments name");
  if (events_.active()) {
    events_.publish(Event{executor_.now(), Component{ComponentKind::link, name_},
                          ImpairmentChange{route_, &impairments_}});
  }
}

namespace {

LinkMessageKind kind_of(const LinkMessage& message) {
  switch (message.index()) {
    case 0: return LinkMessageKind::operator_control;
    case 1: return LinkMessageKind::feedback;
    case 2: return LinkMessageKind::video_frame;
    case 3: return LinkMessageKind::ping;
    default: return LinkMessageKind::pong;
  }
}

}  // namespace

void LinkDirection::publish(LinkOutcome outcome, const LinkMessage& message,
                            std::size_t size_bytes, std::uint64_t message_id, DropReason reason) {
  events_.publish(Event{executor_.now(), Component{ComponentKind::link, name_},
                        LinkEvent{route_, outcome, kind_of(message), reason, size_bytes, message_id}});
}

void LinkDirection::drop(const LinkMessage& message, std::size_t size_bytes,
                         std::uint64_t message_id, DropReason reason) {
  ++counters_.dropped;
  if (events_.active()) publish(LinkOutcome::dropped, message, size_bytes, message_id, reason);
}

void LinkDirection::outage_for(Micros duration) {
  const SimTime before = outage_until_;
  outage_until_ = std::max(outage_until_, executor_.now() + duration);
  OCP_INVARIANT(outage_until_ >= before, "an outage is never shortened by a later one");
}

// What every handler that moves a message leaves true: each copy put on the link (a sent
// message, a duplicate) is delivered, dropped or still in flight, exactly once.
void LinkDirection::check_tally() const {
  OCP_INVARIANT(counters_.sent + counters_.duplicated ==
                        counters_.delivered + counters_.dropped + counters_.in_flight ||
                    OCP_MUTATED(delivered_counted_twice),
                "link tally: sent + duplicated == delivered + dropped + in_flight");
  OCP_INVARIANT(in_flight_.size() == free_in_flight_.size() + counters_.in_flight,
                "every slot of the in-flight pool is either free or holds one message in flight");
}

bool LinkDirection::is_down() const { return impairments_.down || executor_.now() < outage_until_; }

double LinkDirection::uniform_unit() {
  constexpr int mantissa_bits = 53;
  return static_cast<double>(random_() >> (64 - mantissa_bits)) * 0x1.0p-53;
}

Micros LinkDirection::jitter_sample() {
  const auto spread = impairments_.jitter.count();
  if (spread <= 0) {
    return Micros{0};
  }
  switch (impairments_.jitter_kind) {
    case Impairments::JitterKind::none:
      return Micros{0};
    case Impairments::JitterKind::uniform: {
      // Uniform integer in [-spread, +spread].
      const auto choices = static_cast<double>(2 * spread + 1);
      const auto offset = static_cast<std::int64_t>(uniform_unit() * choices);
      return Micros{std::min(offset, 2 * spread) - spread};
    }
    case Impairments::JitterKind::normal: {
      // Box–Muller; 1 - u keeps the logarithm's argument in (0, 1].
      const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform_unit()));
      const double angle = 2.0 * std::numbers::pi * uniform_unit();
      return Micros{std::llround(radius * std::cos(angle) * static_cast<double>(spread))};
    }
  }
  return Micros{0};
}

DropReason LinkDirection::lost_in_transit() {
  if (impairments_.burst_loss) {
    // Gilbert–Elliott: move the two-state chain one step, then lose with that state's rate.
    const double transition = uniform_unit();
    if (in_bad_state_) {
      in_bad_state_ = transition >= impairments_.bad_to_good_probability;
    } else {
      in_bad_state_ = transition < impairments_.good_to_bad_probability;
    }
    const double loss = in_bad_state_ ? impairments_.loss_in_bad : impairments_.loss_in_good;
    if (loss > 0.0 && uniform_unit() < loss) {
      return DropReason::burst_loss;
    }
  }
  if (impairments_.loss_probability > 0.0 && uniform_unit() < impairments_.loss_probability) {
    return DropReason::random_loss;
  }
  return DropReason::none;
}

std::size_t LinkDirection::backlog_bytes(SimTime now) const {
  if (impairments_.trace) return trace_queue_.queued_bytes(now);
  if (impairments_.bandwidth_bits_per_second <= 0.0 || link_free_at_ <= now) {
    return 0;
  }
  const double backlog_seconds = static_cast<double>((link_free_at_ - now).count()) / micros_per_second;
  return static_cast<std::size_t>(
      std::ceil(backlog_seconds * impairments_.bandwidth_bits_per_second / bits_per_byte - 1e-9));
}

const DirectionCounters& LinkDirection::counters() const {
  counters_.queue_depth_bytes = backlog_bytes(executor_.now());
  return counters_;
}

std::optional<SimTime> LinkDirection::queue_for_capacity(SimTime now, std::size_t size_bytes) {
  if (impairments_.trace) {
    return trace_queue_.enqueue(now, size_bytes,
                                TraceQueue::Limits{impairments_.queue_limit_bytes, impairments_.queue_limit_packets});
  }
  if (impairments_.bandwidth_bits_per_second <= 0.0) return now;
  // Serialisation: a FIFO queue drained at the bandwidth cap, tail-dropping beyond its limit.
  // The queue holds every byte not yet on the wire, including the message being sent.
  if (impairments_.queue_limit_bytes > 0 && backlog_bytes(now) + size_bytes > impairments_.queue_limit_bytes) {
    return std::nullopt;
  }
  const double transmit_micros = static_cast<double>(size_bytes) * bits_per_byte * micros_per_second /
                                 impairments_.bandwidth_bits_per_second;
  const SimTime start = std::max(now, link_free_at_);
  link_free_at_ = start + Micros{static_cast<std::int64_t>(std::ceil(transmit_micros - 1e-9))};
  OCP_INVARIANT(link_free_at_ >= now, "the serialiser is busy until now or later once a message is queued");
  return link_free_at_;
}

void LinkDirection::send(LinkMessage message) {
  const SimTime now = executor_.now();
  const std::size_t size_bytes = wire_size_bytes(message);
  ++counters_.sent;
  counters_.bytes_sent += size_bytes;
  const std::uint64_t message_id = next_message_id_++;
  if (events_.active()) publish(LinkOutcome::sent, message, size_bytes, message_id);
  const bool replaying = impairments_.replay && !impairments_.replay->route(route_).empty();
  if (is_down()) {
    if (replaying) ++replay_next_;   // the n-th message stays the n-th of the recording
    drop(message, size_bytes, message_id, DropReason::outage);
    check_tally();
    return;
  }
  if (counters_.in_flight >= in_flight_limit_) {
    if (replaying) ++replay_next_;
    drop(message, size_bytes, message_id, DropReason::in_flight_limit);
    check_tally();
    return;
  }
  if (replaying) {
    send_replayed(std::move(message), size_bytes, message_id);
    check_tally();
    return;
  }

  const std::optional<SimTime> on_wire_at = queue_for_capacity(now, size_bytes);
  if (!on_wire_at) {
    drop(message, size_bytes, message_id, DropReason::queue_full);
    check_tally();
    return;
  }
  OCP_INVARIANT(*on_wire_at >= now, "a message is on the wire no earlier than it was sent");

  // Loss happens in transit, after the message used its share of the bandwidth.
  if (const DropReason lost = lost_in_transit(); lost != DropReason::none) {
    drop(message, size_bytes, message_id, lost);
    check_tally();
    return;
  }

  const Micros delay = std::max(Micros{0}, impairments_.delay + jitter_sample());
  SimTime deliver_at = *on_wire_at + delay;
  const bool reordered = impairments_.reorder_probability > 0.0 && uniform_unit() < impairments_.reorder_probability;
  if (reordered) {
    // Held back without holding back the others: later messages may overtake it.
    deliver_at += impairments_.reorder_extra_delay;
  } else {
    // Jitter alone never reorders: a message is not delivered before its predecessor.
    deliver_at = std::max(deliver_at, last_delivery_at_);
    last_delivery_at_ = deliver_at;
  }
  OCP_INVARIANT(deliver_at >= now, "a message is never delivered before it was sent");

  if (impairments_.duplicate_probability > 0.0 && uniform_unit() < impairments_.duplicate_probability &&
      counters_.in_flight + 1 < in_flight_limit_) {
    ++counters_.duplicated;
    if (events_.active()) publish(LinkOutcome::duplicated, message, size_bytes, message_id);
    schedule_delivery(deliver_at, message, size_bytes, message_id);
  }
  schedule_delivery(deliver_at, std::move(message), size_bytes, message_id);
  OCP_INVARIANT(counters_.in_flight <= in_flight_limit_, "a send never puts the pool beyond its in-flight limit");
  OCP_INVARIANT(counters_.sent + 1 == next_message_id_, "message ids are dense: the n-th message sent has id n");
  check_tally();
}

void LinkDirection::send_replayed(LinkMessage message, std::size_t size_bytes, std::uint64_t message_id) {
  const std::uint64_t replayed_before = replay_next_;
  const RecordedMessage& recorded = impairments_.replay->nth(route_, replay_next_++);
  OCP_INVARIANT(replay_next_ == replayed_before + 1, "each replayed message uses up exactly one recorded outcome");
  if (recorded.lost) {
    drop(message, size_bytes, message_id, DropReason::recorded_loss);
    return;
  }
  // Exactly the recorded delay: the recording already holds any queueing and reordering.
  schedule_delivery(executor_.now() + recorded.delay, std::move(message), size_bytes, message_id);
}

void LinkDirection::schedule_delivery(SimTime deliver_at, LinkMessage message, std::size_t size_bytes,
                                      std::uint64_t message_id) {
  ++counters_.in_flight;
  std::uint32_t slot;
  if (!free_in_flight_.empty()) {
    slot = free_in_flight_.back();
    free_in_flight_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(in_flight_.size());
    in_flight_.emplace_back();
  }
  InFlight& flight = in_flight_[slot];
  flight.message = std::move(message);
  flight.size_bytes = size_bytes;
  flight.message_id = message_id;
  flight.timer = executor_.call_at(deliver_at, [this, slot] { deliver(slot); });
  OCP_INVARIANT(flight.timer != 0, "a message in flight holds a live timer (0 marks a free slot)");
  OCP_INVARIANT(counters_.in_flight <= in_flight_.size(), "every message in flight has a slot of the pool");
}

void LinkDirection::deliver(std::uint32_t slot) {
  // Out of the pool before anyone runs: the receiver may send, which may grow the pool.
  InFlight& flight = in_flight_[slot];
  LinkMessage message = std::move(flight.message);
  const std::size_t size_bytes = flight.size_bytes;
  const std::uint64_t message_id = flight.message_id;
  flight.timer = 0;
  free_in_flight_.push_back(slot);
  --counters_.in_flight;
  ++counters_.delivered;
#ifdef OCP_MUTANTS
  if (mutant_active(Mutant::delivered_counted_twice)) ++counters_.delivered;
#endif
  counters_.bytes_delivered += size_bytes;
  if (events_.active()) publish(LinkOutcome::delivered, message, size_bytes, message_id);
  // Checked before the receiver runs: it may send on this direction, which checks again.
  OCP_INVARIANT(counters_.bytes_delivered <= counters_.bytes_sent * 2,
                "bytes delivered never exceed the bytes sent and their duplicates");
  check_tally();
  if (receiver_) {
    receiver_(std::move(message));
  }
}

ComChannel::ComChannel(Executor& executor, std::uint64_t seed, std::string name)
    : ComChannel(executor, executor, seed, std::move(name)) {}

ComChannel::ComChannel(Executor& player_side, Executor& streamer_side, std::uint64_t seed, std::string name)
    : name_(std::move(name)), to_streamer_(player_side, mix_seed(seed)), to_player_(streamer_side, mix_seed(~seed)) {
  to_streamer_.set_identity(name_, LinkRoute::to_streamer);
  to_player_.set_identity(name_, LinkRoute::to_player);
  to_streamer_.events().set_parent(&events_);
  to_player_.events().set_parent(&events_);
}

void ComChannel::set_impairments(const Impairments& impairments) {
  to_streamer_.set_impairments(impairments);
  to_player_.set_impairments(impairments);
}

}  // namespace ocp
