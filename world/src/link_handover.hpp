#pragma once
// LinkHandover: link messages handed from the thread that delivered them to the thread whose
// part receives them (World::set_streamer_threads). Messages queue under a mutex and one task
// per batch is posted to the receiving thread: a Player frame that sends to 500 Streamers of a
// thread wakes that thread once, not 500 times. Bounded by what the link delivers: a link
// message is handed over once, and the receiving thread drains everything queued.
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

  // Any thread.
  void push(HandedMessage&& handed) {
    bool wake = false;
    {
      const std::lock_guard lock(mutex_);
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
