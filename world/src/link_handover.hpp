#pragma once
// LinkHandover: link messages handed from the thread that delivered them to the thread whose
// part receives them (World::set_streamer_threads). Messages queue under a mutex and one task
// per batch is posted to the receiving thread: a Player frame that sends to 500 Streamers of a
// thread wakes that thread once, not 500 times. The receiving thread drains everything queued
// at each wake-up; a thread that stops draining loses the messages beyond max_queued, as an
// overloaded com channel would.
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "ocp/link_messages.hpp"
#include "world/world.hpp"

namespace ocp {

struct HandedMessage {
  StreamerCore* streamer = nullptr;      // to this Streamer, or (nullptr) …
  const std::string* vehicle = nullptr;  // … to the Player, from this vehicle
  LinkMessage message;
};

class LinkHandover {
 public:
  using Deliver = std::function<void(HandedMessage&&)>;
  LinkHandover(StreamerThread::Poster post, Deliver deliver) : post_(std::move(post)), deliver_(std::move(deliver)) {}

  static constexpr std::size_t max_queued = 1 << 18;   // > 1 s of a 1 000-vehicle fleet's link traffic

  // Any thread.
  void push(HandedMessage&& handed) {
    bool wake = false;
    {
      const std::lock_guard lock(mutex_);
      if (queue_.size() >= max_queued) return;
      queue_.push_back(std::move(handed));
      wake = !posted_;
      posted_ = true;
    }
    if (wake) post_([this] { drain(); });
  }

 private:
  // The receiving thread only.
  void drain() {
    {
      const std::lock_guard lock(mutex_);
      draining_.swap(queue_);
      posted_ = false;
    }
    for (HandedMessage& handed : draining_) deliver_(std::move(handed));
    draining_.clear();   // keeps its capacity: no allocation per batch once warm
  }

  StreamerThread::Poster post_;
  Deliver deliver_;
  std::mutex mutex_;
  std::vector<HandedMessage> queue_;
  bool posted_ = false;
  std::vector<HandedMessage> draining_;
};

}  // namespace ocp
