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

ControlTicker::ControlTicker(Executor& executor, Micros period, std::size_t slots)
    : executor_(executor),
      period_(period),
      step_(period / static_cast<std::int64_t>(usable_slots(period, slots))),
      slots_(usable_slots(period, slots)) {
  assert(period_.count() > 0);
}

ControlTicker::~ControlTicker() {
  if (timer_ != 0) executor_.cancel(timer_);
}

ControlTicker::Member ControlTicker::add(TickHandler on_tick) {
  const bool idle = live_ == 0;
  if (idle) added_ = 0;
  const Member member{added_++ % slots_.size(), next_id_++};
  slots_[member.slot].push_back(Entry{member.id, std::move(on_tick)});
  ++live_;
  if (idle && !firing_) {   // (refilled inside a tick, the running fire() re-arms)
    next_slot_ = member.slot;   // slot 0: added_ was reset
    next_deadline_ = executor_.now();
    arm();
  }
  return member;
}

void ControlTicker::remove(Member member) {
  if (member.id == 0 || member.slot >= slots_.size()) return;
  for (Entry& entry : slots_[member.slot]) {
    if (entry.id != member.id || !entry.on_tick) continue;
    entry.on_tick = nullptr;
    --live_;
    needs_compaction_ = true;
    break;
  }
  if (!firing_) compact();
  if (live_ == 0 && !firing_ && timer_ != 0) {
    executor_.cancel(timer_);
    timer_ = 0;
  }
}

void ControlTicker::compact() {
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
  // Index loop: a handler may add members (appended, ticked from their next deadline on) or
  // remove them (emptied in place).
  auto& slot = slots_[next_slot_];
  const std::size_t count = slot.size();
  for (std::size_t index = 0; index < count; ++index) {
    if (slot[index].on_tick) slot[index].on_tick(deadline);
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
