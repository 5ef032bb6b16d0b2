#pragma once
// LinkHandover: link messages handed from the thread that delivered them to the thread whose
// part receives them (World::set_streamer_threads). Messages queue under a mutex and one task
// per batch is posted to the receiving thread: a Player frame that sends to 500 Streamers of a
// thread wakes that thread once, not 500 times. The receiving thread drains everything queued
// at each wake-up; a thread that stops draining loses the messages beyond max_queued, as an
// overloaded com channel would — and says so: once when an episode of drops starts, once with
// the count when it ends (the first drain that found nothing dropped), never per message.
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "ocp/invariant.hpp"
#include "ocp/link_messages.hpp"

// Below the World that uses it: the hand-over knows a Streamer only by a pointer, and takes
// the receiving thread's poster as a plain function (World's StreamerThread::Poster).
namespace ocp {

class StreamerCore;

// Where a handed-over message goes: to a Streamer, or to the Player from a vehicle.
struct ToStreamer {
  StreamerCore* streamer;
};
struct ToPlayer {
  const std::string* from_vehicle;
};

struct HandedMessage {
  std::variant<ToStreamer, ToPlayer> destination;
  LinkMessage message;
};

class LinkHandover {
 public:
  using Deliver = std::function<void(HandedMessage&&)>;
  // On the receiving thread: dropping started (dropped = 0), or ended after `dropped` messages.
  using OnOverflow = std::function<void(std::uint64_t dropped)>;
  static constexpr std::size_t default_max_queued = 1 << 18;   // > 1 s of a 1 000-vehicle fleet's link traffic

  using Poster = std::function<void(std::function<void()>)>;
  LinkHandover(Poster post, Deliver deliver, OnOverflow on_overflow,
               std::size_t max_queued = default_max_queued)
      : post_(std::move(post)),
        deliver_(std::move(deliver)),
        on_overflow_(std::move(on_overflow)),
        max_queued_(max_queued) {}

  // Any thread.
  void push(HandedMessage&& handed) {
    bool wake = false;
    {
      const std::lock_guard lock(mutex_);
      if (queue_.size() >= max_queued_) {
        ++dropped_;
        return;
      }
      queue_.push_back(std::move(handed));
      OCP_INVARIANT(queue_.size() <= max_queued_, "a hand-over queue never holds more than max_queued messages");
      wake = !posted_;
      posted_ = true;
    }
    if (wake) post_([this] { drain(); });
  }

 private:
  // The receiving thread only.
  void drain() {
    std::uint64_t dropped = 0;
    {
      const std::lock_guard lock(mutex_);
      draining_.swap(queue_);
      posted_ = false;
      std::swap(dropped, dropped_);
    }
    for (HandedMessage& handed : draining_) deliver_(std::move(handed));
    draining_.clear();   // keeps its capacity: no allocation per batch once warm
    if (dropped > 0) {
      if (episode_dropped_ == 0) on_overflow_(0);
      episode_dropped_ += dropped;
    } else if (episode_dropped_ > 0) {
      on_overflow_(std::exchange(episode_dropped_, 0));
    }
  }

  Poster post_;
  Deliver deliver_;
  OnOverflow on_overflow_;
  const std::size_t max_queued_;
  std::mutex mutex_;
  std::vector<HandedMessage> queue_;
  bool posted_ = false;
  std::uint64_t dropped_ = 0;          // since the last drain (under the mutex)
  std::vector<HandedMessage> draining_;
  std::uint64_t episode_dropped_ = 0;  // receiving thread only
};

}  // namespace ocp
