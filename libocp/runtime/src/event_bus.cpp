// EventBus (see event_bus.hpp).
#include "ocp/event_bus.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "ocp/invariant.hpp"

namespace ocp {

struct EventBus::Subscription::Registry {
  struct Slot {
    std::uint64_t id;
    Handler handler;   // empty once unsubscribed during a publish; compacted afterwards
  };
  std::vector<Slot> slots;
  std::size_t live = 0;
  std::uint64_t next_id = 1;
  int publishing = 0;   // nesting depth: slots are only erased when no publish is running
  bool needs_compaction = false;

  void remove(std::uint64_t id) {
    for (auto& slot : slots) {
      if (slot.id != id || !slot.handler) continue;
      slot.handler = nullptr;
      --live;
      needs_compaction = true;
      break;
    }
    compact_if_idle();
    OCP_INVARIANT(live <= slots.size(), "each live subscriber has its slot");
  }
  void compact_if_idle() {
    if (publishing > 0 || !needs_compaction) return;
    std::erase_if(slots, [](const Slot& slot) { return !slot.handler; });
    needs_compaction = false;
    OCP_INVARIANT(slots.size() == live, "once compacted, the slots are exactly the live subscribers");
  }
};

EventBus::Subscription::Subscription(std::weak_ptr<Registry> registry, std::uint64_t id)
    : registry_(std::move(registry)), id_(id) {}

EventBus::Subscription::Subscription(Subscription&& other) noexcept
    : registry_(std::move(other.registry_)), id_(other.id_) {
  other.registry_.reset();
}

EventBus::Subscription& EventBus::Subscription::operator=(Subscription&& other) noexcept {
  if (this != &other) {
    reset();
    registry_ = std::move(other.registry_);
    id_ = other.id_;
    other.registry_.reset();
  }
  return *this;
}

void EventBus::Subscription::reset() {
  if (auto registry = registry_.lock()) registry->remove(id_);
  registry_.reset();
}

EventBus::EventBus()
    : registry_(std::make_shared<Subscription::Registry>()), live_(&registry_->live) {}

EventBus::~EventBus() = default;

EventBus::Subscription EventBus::subscribe(Handler handler) {
  if (!handler) return {};
  if (registry_->live >= max_subscribers) {
    throw std::length_error("event bus: " + std::to_string(max_subscribers) +
                            " live subscribers (the limit): a subscription made again and again and never dropped");
  }
  const std::uint64_t id = registry_->next_id++;
  registry_->slots.push_back({id, std::move(handler)});
  ++registry_->live;
  OCP_INVARIANT(registry_->live <= max_subscribers, "subscribe never takes a bus beyond its subscriber limit");
  OCP_INVARIANT(registry_->live <= registry_->slots.size(), "each live subscriber has its slot");
  OCP_INVARIANT(registry_->slots.back().id + 1 == registry_->next_id, "subscription ids are handed out in order");
  return Subscription(registry_, id);
}

void EventBus::publish(const Event& event) const {
  if (*live_ > 0) {
    // Keep the registry alive even if a handler destroys this bus's owner's subscriptions.
    const auto registry = registry_;
    ++registry->publishing;
    // Index loop over the count at entry: handlers added during this publish wait for the
    // next one, and push_back may reallocate, so no references are held across a call.
    const std::size_t count = registry->slots.size();
    for (std::size_t i = 0; i < count; ++i) {
      if (!registry->slots[i].handler) continue;
      const Handler handler = registry->slots[i].handler;  // the slot may be cleared inside
      handler(event);
    }
    --registry->publishing;
    registry->compact_if_idle();
    OCP_INVARIANT(registry->publishing >= 0, "every publish that entered has left");
  }
  if (parent_ != nullptr) parent_->publish(event);
}

}  // namespace ocp
