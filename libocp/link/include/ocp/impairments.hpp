#pragma once
// Impairments of one direction of the fake com channel (com_channel.hpp), changeable at any
// moment. Kept apart so that events (events.hpp) can describe a change without the channel.
#include <cstddef>
#include <memory>

#include "ocp/time.hpp"

namespace ocp {

class DeliveryTrace;  // delivery_trace.hpp
class LinkRecording;  // link_recording.hpp

struct Impairments {
  Micros delay{0};                   // fixed one-way delay
  enum class JitterKind { none, uniform, normal };
  JitterKind jitter_kind = JitterKind::none;
  Micros jitter{0};                  // uniform: ±jitter; normal: standard deviation
  double loss_probability = 0.0;     // independent random loss, 0..1
  // Gilbert–Elliott burst loss: two-state Markov chain (good/bad), evaluated per message.
  bool burst_loss = false;
  double good_to_bad_probability = 0.0;
  double bad_to_good_probability = 1.0;
  double loss_in_good = 0.0;
  double loss_in_bad = 1.0;
  double bandwidth_bits_per_second = 0.0;  // 0 = unlimited; otherwise FIFO serialisation queue
  std::size_t queue_limit_bytes = 0;       // 0 = unlimited; tail-drop beyond it
  // Trace-driven capacity (Mahimahi format) instead of `bandwidth_bits_per_second`: a drop-tail
  // queue limited by queue_limit_bytes and/or queue_limit_packets (neither: TraceQueue's default).
  std::shared_ptr<const DeliveryTrace> trace = nullptr;
  std::size_t queue_limit_packets = 0;     // 0 = no packet limit (trace-driven links only)
  double duplicate_probability = 0.0;
  double reorder_probability = 0.0;        // a reordered message gets `reorder_extra_delay`
  Micros reorder_extra_delay{0};
  bool down = false;                       // outage: everything sent while down is lost
  // Replay of a recorded link (docs/link-recording.md): the direction's n-th message gets the
  // recording's n-th outcome for its route (delay or loss), looping; it replaces every other
  // field above except `down` and outages, which still drop (and use up their entry).
  std::shared_ptr<const LinkRecording> replay = nullptr;
};

}  // namespace ocp
