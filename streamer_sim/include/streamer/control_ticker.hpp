#pragma once
// ControlTicker: one executor timer for the control ticks of many Streamers on one executor.
// SPEC §3.2 asks each vehicle for a control message every control period; nothing asks a
// vehicle for a timer of its own. At fleet scale one timer per vehicle costs one executor task
// (a queue insert, a clock read, a wake-up) per vehicle per period; a ticker costs one per slot.
//
// Slots spread the fleet's ticks over the period: member j (in the order they were added)
// belongs to slot j mod slots, and slot s ticks at t0 + k·period + s·(period / slots), t0 being
// when the first member was added to an idle ticker, plus the ticker's phase. Tickers on
// different threads take turns through their phases (World gives thread i of n a phase of
// i/n of a slot), so no two threads' slots fall on one instant. One slot is the plain case:
// every member ticks at t0 + k·period, so a ticker with one member runs exactly the task a
// PeriodicTimer would (same deadlines, same scheduling order: the golden trace does not
// change). Many slots keep a big fleet's ticks from all falling at one instant, which would
// make the last vehicle of the batch late by the whole batch's work.
//
// A slot's members tick in the order they were added, each with the slot's deadline. A slot
// more than a period behind skips whole periods (counted), as PeriodicTimer does. Like every
// core object: single-threaded, on the executor's thread.
#include <cstdint>
#include <functional>
#include <vector>

#include "ocp/executor.hpp"

namespace ocp {

class ControlTicker {
 public:
  using TickHandler = std::function<void(SimTime deadline)>;
  struct Member {
    std::size_t slot = 0;
    std::uint64_t id = 0;   // 0: not a member
  };

  // period > 0; slots in [1, period in µs] (clamped), period divisible by slots for exact phases;
  // phase in [0, period) (clamped).
  ControlTicker(Executor& executor, Micros period, std::size_t slots = 1, Micros phase = Micros{0});
  ~ControlTicker();
  ControlTicker(const ControlTicker&) = delete;
  ControlTicker& operator=(const ControlTicker&) = delete;

  // The member's first tick is its slot's next deadline (now + phase, for the first member of an
  // idle ticker). May be called from inside a tick.
  Member add(TickHandler on_tick);
  // Harmless for a member already removed; may be called from inside a tick.
  void remove(Member member);

  Micros period() const { return period_; }
  // The time between two slots of a ticker built with `period` and `slots` (clamped as above).
  static Micros slot_step(Micros period, std::size_t slots);
  std::size_t members() const { return live_; }
  std::uint64_t missed_periods() const { return missed_periods_; }

 private:
  struct Entry {
    std::uint64_t id;
    std::size_t slot;
    TickHandler on_tick;   // empty once removed; compacted when no tick is running
  };
  void fire();
  void arm();
  void advance();   // to the next slot that has members
  void compact();   // places the members that joined during a tick, drops removed ones

  Executor& executor_;
  Micros period_;
  Micros step_;
  Micros phase_;
  std::vector<std::vector<Entry>> slots_;
  std::vector<Entry> joining_;       // added during a tick, placed in their slots after it
  std::size_t next_slot_ = 0;        // the slot the armed timer is for
  SimTime next_deadline_{};
  Executor::TimerId timer_ = 0;
  std::uint64_t next_id_ = 1;
  std::size_t added_ = 0;            // since the ticker was last idle: picks the slot
  std::size_t live_ = 0;
  bool firing_ = false;
  bool needs_compaction_ = false;
  std::uint64_t missed_periods_ = 0;
};

}  // namespace ocp
