#pragma once
// EventBus: publish/subscribe for the typed events of events.hpp, owned by each component.
//
//   auto subscription = streamer.events().subscribe([&](const Event& event) { … });
//   … events arrive, on the executor's thread, while `subscription` lives …
//
// * Any number of subscribers, added and removed at any time — also from inside a handler
//   (a handler removed during a publish is not called again; one added is called from the
//   next publish on). Subscription is an RAII handle; it may outlive the bus.
// * A bus may have a parent (World's bus is the parent of every component's bus in it): what
//   is published on the child reaches the child's subscribers, then the parent's.
// * Nil cost when nobody listens: publishers test active() — one branch — before building an
//   event, so a run without subscribers does exactly the work it did before events existed.
// Single-threaded like the cores: publish and subscribe on the executor's thread.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ocp/events.hpp"

namespace ocp {

class EventBus {
 public:
  using Handler = std::function<void(const Event&)>;

  class Subscription {
   public:
    Subscription() = default;
    ~Subscription() { reset(); }
    Subscription(Subscription&& other) noexcept;
    Subscription& operator=(Subscription&& other) noexcept;
    Subscription(const Subscription&) = delete;
    Subscription& operator=(const Subscription&) = delete;
    void reset();                                   // unsubscribes now
    bool active() const { return !registry_.expired(); }

   private:
    friend class EventBus;
    struct Registry;
    Subscription(std::weak_ptr<Registry> registry, std::uint64_t id);
    std::weak_ptr<Registry> registry_;
    std::uint64_t id_ = 0;
  };

  EventBus();
  ~EventBus();
  EventBus(const EventBus&) = delete;
  EventBus& operator=(const EventBus&) = delete;

  // The parent must outlive this bus, or be unset first.
  void set_parent(EventBus* parent) { parent_ = parent; }

  // The most live subscribers one bus takes: every tool subscribes a few, so more is a leak (a
  // subscription made per event or per connection and never dropped). One more throws
  // std::length_error naming the limit.
  static constexpr std::size_t max_subscribers = 4096;
  [[nodiscard]] Subscription subscribe(Handler handler);

  // True when a publish would reach anybody (here or up the parent chain).
  bool active() const noexcept { return *live_ > 0 || (parent_ != nullptr && parent_->active()); }

  void publish(const Event& event) const;

 private:
  std::shared_ptr<Subscription::Registry> registry_;
  const std::size_t* live_;   // registry_->live, read on every active() without a deref chain
  EventBus* parent_ = nullptr;
};

}  // namespace ocp
