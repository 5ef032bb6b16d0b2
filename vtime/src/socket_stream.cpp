// SocketStream (socket_stream.hpp).
#include "socket_stream.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <utility>

namespace ocp::vtime {

namespace {
// How long to wait for bytes the client said it wrote (they are on loopback: microseconds).
constexpr int arrival_wait_ms = 2000;
constexpr std::size_t read_chunk = 65536;
}  // namespace

void ClientWrites::merge(const WrittenCount& count) {
  written = std::max(written, count.written);
  if (count.first_write_end != 0 && (first_write_end == 0 || count.first_write_end < first_write_end)) {
    first_write_end = count.first_write_end;
  }
  no_delay = count.no_delay != 0;
}

void ClientWrites::take(ClientWrites& other) {
  merge({0, other.no_delay ? 1u : 0u, other.written, std::exchange(other.first_write_end, 0)});
}

SocketStream::SocketStream(VirtualExecutor& executor, int fd, std::uint16_t peer_port, std::string name)
    : executor_(executor), fd_(fd), peer_port_(peer_port), name_(std::move(name)) {}

SocketStream::~SocketStream() { close_socket(); }

void SocketStream::close_socket() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void SocketStream::set_handlers(ByteStreamHandlers handlers) {
  handlers_ = std::move(handlers);
  have_handlers_ = true;
  if (!early_.empty()) hand_over(std::exchange(early_, {}));
  if (early_close_) hand_over_close("connection closed by peer");
}

void SocketStream::write(std::string_view bytes) {
  if (!open_ || close_requested_) return;
  outbox_.append(bytes);
}

void SocketStream::close() {
  open_ = false;
  close_requested_ = true;
}

void SocketStream::set_no_delay(bool on) {
  if (fd_ < 0) return;
  const int value = on ? 1 : 0;
  (void)setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &value, sizeof value);
}

std::size_t SocketStream::flush(bool& changed) {
  if (fd_ < 0) return 0;
  std::size_t sent = 0;
  while (!outbox_.empty()) {
    const ssize_t wrote = ::send(fd_, outbox_.data(), outbox_.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (wrote <= 0) {
      if (wrote < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) break;
      outbox_.clear();   // reset by the peer: what is left has nowhere to go
      break;
    }
    outbox_.erase(0, static_cast<std::size_t>(wrote));
    sent += static_cast<std::size_t>(wrote);
  }
  written_total_ += sent;
  if (sent > 0) {
    changed = true;
    send_unsent(nagle_.acknowledged(executor_.now()));   // the ACK rides on our bytes
  }
  if (close_requested_ && (outbox_.empty() || eof_seen_)) {
    close_socket();
    changed = true;
  }
  return sent;
}

std::size_t SocketStream::take(const ClientWrites& reported, bool expect_eof) {
  const std::uint64_t expected = reported.written;
  if (fd_ < 0 || eof_seen_) return 0;
  std::string got;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(arrival_wait_ms);
  char buffer[read_chunk];
  for (;;) {
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n > 0) {
      got.append(buffer, static_cast<std::size_t>(n));
      received_total_ += static_cast<std::uint64_t>(n);
      continue;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
      eof_seen_ = true;
      break;
    }
    const bool owed = received_total_ < expected || expect_eof;
    if (!owed || std::chrono::steady_clock::now() >= give_up) break;
    pollfd wait{fd_, POLLIN, 0};
    (void)::poll(&wait, 1, 1);
  }
  const std::size_t size = got.size();
  unsent_ += got;
  send_unsent(nagle_.arrived(received_total_, reported.first_write_end, reported.no_delay, executor_.now()));
  if (eof_seen_) {
    send_unsent(nagle_.closed());
    eof_news_ = true;
    open_ = false;
    hand_over_close("connection closed by peer");
  }
  return size;
}

void SocketStream::send_unsent(std::uint64_t sent_end) {
  const std::uint64_t handed = received_total_ - unsent_.size();
  if (sent_end > handed) {
    const std::size_t count = static_cast<std::size_t>(sent_end - handed);
    hand_over(unsent_.substr(0, count));
    unsent_.erase(0, count);
  }
  schedule_delayed_ack();
}

// Writing nothing to the client, we acknowledge its segment in flight after the delayed-ACK
// time; then what its kernel held goes.
void SocketStream::schedule_delayed_ack() {
  const std::optional<SimTime> due = nagle_.delayed_ack_due();
  if (!due || *due == delayed_ack_at_) return;
  delayed_ack_at_ = *due;
  executor_.call_at(*due, [weak = weak_from_this()] {
    const auto self = weak.lock();
    if (!self || self->fd_ < 0) return;
    const std::optional<SimTime> now_due = self->nagle_.delayed_ack_due();
    if (now_due && *now_due <= self->executor_.now()) self->send_unsent(self->nagle_.acknowledged(self->executor_.now()));
  });
}

void SocketStream::hand_over(std::string bytes) {
  if (!have_handlers_) {
    early_ += bytes;
    return;
  }
  executor_.call_at(executor_.now(), [self = shared_from_this(), bytes = std::move(bytes)] {
    if (self->handlers_.on_bytes) self->handlers_.on_bytes(bytes);
  });
}

void SocketStream::hand_over_close(std::string reason) {
  if (!have_handlers_) {
    early_close_ = true;
    return;
  }
  executor_.call_at(executor_.now(), [self = shared_from_this(), reason = std::move(reason)] {
    if (self->close_requested_) return;   // closed by us meanwhile: no on_closed for a local close
    if (self->handlers_.on_closed) self->handlers_.on_closed(reason);
  });
}

}  // namespace ocp::vtime
