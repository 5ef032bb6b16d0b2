#pragma once
// The fake Oden com channel: a bidirectional link between one Player and one Streamer, with
// independent, injectable impairments per direction that can be changed at any moment.
// Deterministic: every random draw comes from the link's own seeded generator
// (std::mt19937_64, whose output the standard fixes; the distributions are our own code, so
// the same seed gives the same run with any standard library).
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/event_bus.hpp"
#include "ocp/executor.hpp"
#include "ocp/impairments.hpp"
#include "ocp/link.hpp"
#include "ocp/link_events.hpp"
#include "ocp/link_messages.hpp"
#include "ocp/link_recording.hpp"
#include "ocp/trace_queue.hpp"

namespace ocp {

struct DirectionCounters {
  std::uint64_t sent = 0;
  std::uint64_t delivered = 0;
  std::uint64_t dropped = 0;       // random, burst, outage or queue-limit loss
  std::uint64_t duplicated = 0;
  std::uint64_t bytes_sent = 0;
  std::uint64_t bytes_delivered = 0;
  std::size_t queue_depth_bytes = 0;   // bytes waiting for bandwidth
  std::size_t in_flight = 0;           // scheduled but not yet delivered
};

// One direction of a link: the simulated implementation of Link (ocp/link.hpp).
class LinkDirection final : public Link {
 public:
  LinkDirection(Executor& executor, std::uint64_t seed);
  // Who this direction is, for the events it publishes (ComChannel sets it; a bare direction
  // publishes as an unnamed link, route to_streamer). `name` must outlive the direction.
  void set_identity(std::string_view name, LinkRoute route);
  // Destroying a direction with messages in flight is safe: their deliveries are cancelled
  // (the executor must outlive the direction). Not copyable, since in-flight deliveries refer
  // to it.
  ~LinkDirection() override;
  LinkDirection(const LinkDirection&) = delete;
  LinkDirection& operator=(const LinkDirection&) = delete;
  void set_receiver(Receiver receiver) override;
  void set_impairments(const Impairments& impairments);
  const Impairments& impairments() const { return impairments_; }
  // Schedules delivery (or drops) according to the current impairments.
  void send(LinkMessage message) override;
  // Outage for `duration` starting now.
  void outage_for(Micros duration);
  // Counters as of now (queue depth is computed from the serialiser's backlog).
  const DirectionCounters& counters() const;
  // LinkEvent per message sent, delivered or dropped; ImpairmentChange on set_impairments.
  EventBus& events() { return events_; }

  // The most messages (copies included) this direction holds in flight: beyond it a message is
  // dropped (DropReason::in_flight_limit). The default is about three hours of 100 Hz control
  // held back: only a runaway delay or send rate reaches it, and memory stays bounded then.
  static constexpr std::size_t default_in_flight_limit = std::size_t{1} << 20;
  void set_in_flight_limit(std::size_t limit) { in_flight_limit_ = limit; }
  std::size_t in_flight_limit() const { return in_flight_limit_; }

 private:
  bool is_down() const;
  DropReason lost_in_transit();   // none: not lost
  Micros jitter_sample();
  double uniform_unit();  // [0, 1) from 53 random bits
  std::size_t backlog_bytes(SimTime now) const;
  // When the message is on the wire (its last bit sent), or nullopt: tail-dropped by a queue.
  std::optional<SimTime> queue_for_capacity(SimTime now, std::size_t size_bytes);
  void schedule_delivery(SimTime deliver_at, LinkMessage message, std::size_t size_bytes,
                         std::uint64_t message_id);
  void deliver(std::uint32_t slot);
  // Replay (impairments_.replay): the next recorded outcome of this route, instead of the
  // other impairments.
  void send_replayed(LinkMessage message, std::size_t size_bytes, std::uint64_t message_id);
  void publish(LinkOutcome outcome, const LinkMessage& message, std::size_t size_bytes,
               std::uint64_t message_id, DropReason reason = DropReason::none);
  void drop(const LinkMessage& message, std::size_t size_bytes, std::uint64_t message_id,
            DropReason reason);
  // The invariants every handler that moves a message leaves true (com_channel.cpp).
  void check_tally() const;

  Executor& executor_;
  std::mt19937_64 random_;
  Impairments impairments_;
  Receiver receiver_;
  mutable DirectionCounters counters_;
  bool in_bad_state_ = false;
  SimTime link_free_at_{};  // when the bandwidth-limited serialiser is next idle
  mutable TraceQueue trace_queue_;  // trace-driven capacity (impairments_.trace)
  SimTime last_delivery_at_{};  // keeps FIFO order unless reordering is requested
  SimTime outage_until_{};      // outage_for(): down while now < outage_until_
  std::uint64_t replay_next_ = 0;  // messages sent since the replay started
  // Messages in flight wait in a reused pool, so a delivery task captures only (this, slot):
  // std::function keeps that inline, with no allocation per message.
  struct InFlight {
    LinkMessage message;
    std::size_t size_bytes = 0;
    std::uint64_t message_id = 0;
    Executor::TimerId timer = 0;  // 0: the slot is free
  };
  std::vector<InFlight> in_flight_;
  std::vector<std::uint32_t> free_in_flight_;
  EventBus events_;
  std::string_view name_;
  LinkRoute route_ = LinkRoute::to_streamer;
  std::uint64_t next_message_id_ = 1;
  std::size_t in_flight_limit_ = default_in_flight_limit;
};

// A Player ⇄ Streamer link.
class ComChannel {
 public:
  // `name` identifies the link in events (the World uses the vehicle's name).
  ComChannel(Executor& executor, std::uint64_t seed, std::string name = "link");
  // Each direction on its sender's executor (real time with the Player and the Streamer on
  // different threads): it draws its impairments and runs its deliveries there, and the
  // receiver hands each message over to the other thread. Same draws as the one-executor form.
  ComChannel(Executor& player_side, Executor& streamer_side, std::uint64_t seed, std::string name);
  ComChannel(const ComChannel&) = delete;
  ComChannel& operator=(const ComChannel&) = delete;
  LinkDirection& to_streamer() { return to_streamer_; }
  LinkDirection& to_player() { return to_player_; }
  const std::string& name() const { return name_; }
  // Sets the same impairments on both directions.
  void set_impairments(const Impairments& impairments);
  // Both directions' events.
  EventBus& events() { return events_; }

 private:
  std::string name_;
  EventBus events_;   // before the directions: they name it as their parent
  LinkDirection to_streamer_;
  LinkDirection to_player_;
};

}  // namespace ocp
