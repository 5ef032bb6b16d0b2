#include "ocp/pipe.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

constexpr const char* closed_by_peer_reason = "closed by peer";

// One end of an in-memory pipe. Ends refer to each other weakly (a weak_ptr, and a plain
// pointer that the destroyed end clears). Bytes written towards an end
// wait in that end's transit buffer (reused: no allocation per write) and each write is one
// executor task that hands the next `length` bytes over. Writes to one end all have the same
// delay, so their tasks run in write order and the buffer is a FIFO. An end cancels the tasks
// still heading for it when it is destroyed, so they never touch a dead end.
class PipeEnd final : public ByteStream, public std::enable_shared_from_this<PipeEnd> {
 public:
  PipeEnd(Executor& executor, Micros one_way_delay, std::size_t max_chunk_bytes, std::string peer_name)
      : executor_(executor),
        one_way_delay_(one_way_delay),
        max_chunk_bytes_(max_chunk_bytes),
        peer_name_(std::move(peer_name)) {}

  ~PipeEnd() override {
    for (std::size_t i = pending_head_; i < pending_.size(); ++i) executor_.cancel(pending_[i].timer);
    if (peer_end_ != nullptr) peer_end_->peer_end_ = nullptr;
    notify_peer_of_close();
  }

  void connect(const std::shared_ptr<PipeEnd>& peer) {
    peer_ = peer;
    peer_end_ = peer.get();
  }

  void set_handlers(ByteStreamHandlers handlers) override {
    // Shared so a handler may replace the handlers while it runs without destroying itself.
    handlers_ = std::make_shared<const ByteStreamHandlers>(std::move(handlers));
    if (reading_) {
      return;
    }
    reading_ = true;
    // Whatever arrived before reading started is handed over from the executor, not from
    // inside set_handlers, so the caller never sees callbacks re-entering its setup code.
    if (!buffered_.empty() || peer_closed_) {
      executor_.post([weak = weak_from_this()] {
        if (auto self = weak.lock()) {
          self->flush_buffered();
        }
      });
    }
  }

  void write(std::string_view bytes) override {
    if (!open_ || bytes.empty()) {
      return;
    }
    if (peer_end_ != nullptr) {
      peer_end_->enqueue(bytes, one_way_delay_);
    }
  }

  std::size_t queued_bytes() const override {
    const PipeEnd* peer = peer_end_;
    return peer != nullptr ? peer->transit_.size() - peer->transit_head_ + peer->buffered_.size() : 0;
  }

  void close() override {
    if (!open_) {
      return;
    }
    open_ = false;
    notify_peer_of_close();
  }

  bool is_open() const override { return open_; }
  std::string peer_name() const override { return peer_name_; }
  // The other end closed (or is gone) and its close has not reached this end's reader yet.
  bool peer_hung_up() const override {
    return open_ && (peer_closed_ || peer_end_ == nullptr || !peer_end_->open_);
  }

 private:
  void notify_peer_of_close() {
    if (peer_notified_) {
      return;
    }
    peer_notified_ = true;
    // Same delay as data and scheduled after it, so every byte written before close
    // arrives before the close does.
    executor_.call_after(one_way_delay_, [peer = peer_] {
      if (auto end = peer.lock()) {
        end->receive_close();
      }
    });
  }

  // Bytes written by the peer: kept here until their delivery task runs.
  void enqueue(std::string_view bytes, Micros delay) {
    transit_.append(bytes);
    // Captures one pointer, so std::function stores it inline: no allocation per write.
    const auto timer = executor_.call_after(delay, [this] { deliver_next(); });
    pending_.push_back(Pending{timer, bytes.size()});
    OCP_INVARIANT(transit_.size() - transit_head_ >= bytes.size(), "written bytes wait in transit until delivered");
    OCP_INVARIANT_DEEP(transit_bytes_match_pending(), "the bytes in transit are exactly the pending writes' bytes");
  }

  bool transit_bytes_match_pending() const {
    std::size_t pending_bytes = 0;
    for (std::size_t i = pending_head_; i < pending_.size(); ++i) pending_bytes += pending_[i].length;
    return pending_bytes == transit_.size() - transit_head_;
  }

  void deliver_next() {
    const std::size_t length = pending_[pending_head_].length;
    ++pending_head_;
    // The bytes move out of the transit buffer before any handler runs: a handler may write
    // to this end again. When they are all of it (the usual case) that is a swap, not a copy.
    if (transit_head_ == 0 && length == transit_.size()) {
      arrived_.swap(transit_);
      transit_.clear();
    } else {
      arrived_.assign(transit_, transit_head_, length);
      transit_head_ += length;
    }
    drop_delivered();
    OCP_INVARIANT(pending_head_ <= pending_.size() && transit_head_ <= transit_.size(),
                  "a pipe's delivered fronts never pass the end of what was written");
    OCP_INVARIANT(pending_head_ != pending_.size() || transit_head_ == transit_.size(),
                  "no bytes stay in transit once every write is delivered");
    receive(arrived_);
  }

  // With a delay, writes keep arriving while earlier ones wait, so the FIFOs may never run
  // empty: drop their delivered front once it is at least half of them.
  void drop_delivered() {
    if (pending_head_ == pending_.size()) {
      pending_.clear();
      pending_head_ = 0;
    } else if (pending_head_ >= 64 && 2 * pending_head_ >= pending_.size()) {
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(pending_head_));
      pending_head_ = 0;
    }
    if (transit_head_ == transit_.size()) {
      transit_.clear();
      transit_head_ = 0;
    } else if (transit_head_ >= 4096 && 2 * transit_head_ >= transit_.size()) {
      transit_.erase(0, transit_head_);
      transit_head_ = 0;
    }
  }

  void receive(std::string_view data) {
    if (!open_) {
      return;  // closed locally: nothing more is delivered
    }
    if (!reading_ || !buffered_.empty()) {
      buffered_ += data;
      return;
    }
    deliver(data);
  }

  void receive_close() {
    if (peer_closed_) {
      return;
    }
    peer_closed_ = true;
    if (!reading_ || !buffered_.empty()) {
      return;  // reported after the buffered bytes, once reading starts
    }
    report_close();
  }

  void flush_buffered() {
    std::string data = std::move(buffered_);
    buffered_.clear();
    if (!data.empty() && open_) {
      deliver(data);
    }
    if (peer_closed_) {
      report_close();
    }
  }

  void deliver(std::string_view data) {
    // Hold ourselves: a handler may drop the last external reference to this end.
    const auto keep_alive = shared_from_this();
    const std::size_t chunk = max_chunk_bytes_ == 0 ? data.size() : max_chunk_bytes_;
    for (std::size_t offset = 0; offset < data.size() && open_; offset += chunk) {
      const auto handlers = handlers_;
      if (handlers->on_bytes) {
        handlers->on_bytes(data.substr(offset, std::min(chunk, data.size() - offset)));
      }
    }
  }

  void report_close() {
    if (!open_ || close_reported_) {
      return;  // a local close() is never reported back
    }
    close_reported_ = true;
    open_ = false;
    peer_notified_ = true;  // the peer is gone already; nothing to tell it
    const auto keep_alive = shared_from_this();
    const auto handlers = handlers_;
    if (handlers->on_closed) {
      handlers->on_closed(closed_by_peer_reason);
    }
  }

  Executor& executor_;
  Micros one_way_delay_;
  std::size_t max_chunk_bytes_;
  std::string peer_name_;
  std::weak_ptr<PipeEnd> peer_;
  // The same end for the per-write path (no atomic reference count per write); each end's
  // destructor clears the other's pointer.
  PipeEnd* peer_end_ = nullptr;
  std::shared_ptr<const ByteStreamHandlers> handlers_ = std::make_shared<const ByteStreamHandlers>();
  std::string buffered_;   // arrived before the handlers were set (the reader has not started)
  struct Pending {
    Executor::TimerId timer;
    std::size_t length;
  };
  std::string transit_;           // written by the peer, not yet delivered (from transit_head_)
  std::size_t transit_head_ = 0;
  std::vector<Pending> pending_;  // one per write in transit, in order (from pending_head_)
  std::size_t pending_head_ = 0;
  std::string arrived_;           // the bytes being handed to the handler (reused)
  bool reading_ = false;
  bool open_ = true;
  bool peer_closed_ = false;
  bool peer_notified_ = false;
  bool close_reported_ = false;
};

}  // namespace

PipeEnds make_pipe(Executor& executor, PipeOptions options) {
  // Each end reports the other end's name as its peer.
  auto a = std::make_shared<PipeEnd>(executor, options.one_way_delay, options.max_chunk_bytes, options.name_b);
  auto b = std::make_shared<PipeEnd>(executor, options.one_way_delay, options.max_chunk_bytes, options.name_a);
  a->connect(b);
  b->connect(a);
  return PipeEnds{a, b};
}

}  // namespace ocp
