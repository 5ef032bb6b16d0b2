#include "streamer/control_ticker.hpp"

#include <algorithm>
#include <cassert>

namespace ocp {
namespace {

// At least one slot, and no slot shorter than a microsecond.
std::size_t usable_slots(Micros period, std::size_t slots) {
  return std::clamp<std::size_t>(slots, 1, static_cast<std::size_t>(std::max<std::int64_t>(period.count(), 1)));
}

}  // namespace

ControlTicker::ControlTicker(Executor& executor, Micros period, std::size_t slots, Micros phase)
    : executor_(executor),
      period_(period),
      step_(slot_step(period, slots)),
      phase_(std::clamp(phase, Micros{0}, std::max(period - Micros{1}, Micros{0}))),
      slots_(usable_slots(period, slots)) {
  assert(period_.count() > 0);
}

Micros ControlTicker::slot_step(Micros period, std::size_t slots) {
  return period / static_cast<std::int64_t>(usable_slots(period, slots));
}

ControlTicker::~ControlTicker() {
  if (timer_ != 0) executor_.cancel(timer_);
}

ControlTicker::Member ControlTicker::add(TickHandler on_tick) {
  const bool idle = live_ == 0;
  if (idle) added_ = 0;
  const Member member{added_++ % slots_.size(), next_id_++};
  // Not into a slot while a tick runs: the slot's vector may be the one being iterated.
  (firing_ ? joining_ : slots_[member.slot]).push_back(Entry{member.id, member.slot, std::move(on_tick)});
  ++live_;
  if (idle && !firing_) {   // (refilled inside a tick, the running fire() re-arms)
    next_slot_ = member.slot;   // slot 0: added_ was reset
    next_deadline_ = executor_.now() + phase_;
    arm();
  }
  return member;
}

void ControlTicker::remove(Member member) {
  if (member.id == 0 || member.slot >= slots_.size()) return;
  for (auto* entries : {&slots_[member.slot], &joining_}) {
    for (Entry& entry : *entries) {
      if (entry.id != member.id || !entry.on_tick) continue;
      entry.on_tick = nullptr;
      --live_;
      needs_compaction_ = true;
      break;
    }
  }
  if (!firing_) compact();
  if (live_ == 0 && !firing_ && timer_ != 0) {
    executor_.cancel(timer_);
    timer_ = 0;
  }
}

void ControlTicker::compact() {
  for (Entry& entry : joining_) {
    if (entry.on_tick) slots_[entry.slot].push_back(std::move(entry));
  }
  joining_.clear();
  if (!needs_compaction_) return;
  for (auto& slot : slots_) std::erase_if(slot, [](const Entry& entry) { return !entry.on_tick; });
  needs_compaction_ = false;
}

void ControlTicker::arm() {
  timer_ = executor_.call_at(next_deadline_, [this] { fire(); });
}

void ControlTicker::fire() {
  timer_ = 0;
  const SimTime deadline = next_deadline_;
  firing_ = true;
  // A handler may add members (they join after this tick, from their slot's next deadline on)
  // or remove them (emptied in place, erased after this tick): the slot's vector stays put.
  for (Entry& entry : slots_[next_slot_]) {
    if (entry.on_tick) entry.on_tick(deadline);
  }
  firing_ = false;
  compact();
  if (live_ == 0) return;
  advance();
  // A slot later than the rest of the period (period − step) skips whole periods instead of
  // bunching; one merely late runs now, after what is already due. With one slot this is
  // PeriodicTimer's rule: a deadline already passed is skipped.
  const SimTime now = executor_.now();
  const SimTime tolerated = next_deadline_ + (period_ - step_);
  if (tolerated < now) {
    const auto skipped = ((now - tolerated).count() + period_.count() - 1) / period_.count();
    missed_periods_ += static_cast<std::uint64_t>(skipped);
    next_deadline_ += period_ * skipped;
  }
  arm();
}

void ControlTicker::advance() {
  for (std::size_t step = 0; step < slots_.size(); ++step) {
    next_slot_ = (next_slot_ + 1) % slots_.size();
    next_deadline_ += step_;
    if (next_slot_ == 0) next_deadline_ += period_ - step_ * static_cast<std::int64_t>(slots_.size());
    if (!slots_[next_slot_].empty()) return;
  }
}

}  // namespace ocp
