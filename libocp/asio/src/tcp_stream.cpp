#include "ocp/asio/tcp_stream.hpp"

#include <linux/sockios.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <array>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <string>

namespace ocp {
namespace {

namespace asio = boost::asio;
using boost::system::error_code;

std::string describe_close(const error_code& error) {
  if (error == asio::error::eof) {
    return "connection closed by peer";
  }
  if (error == asio::error::connection_reset || error == asio::error::broken_pipe) {
    return "connection reset";
  }
  return "transport error: " + error.message();
}

// Reads run continuously once handlers are set. A write with nothing queued goes straight to
// the socket (non-blocking `send`): a frame normally fits whole, and then no completion
// handler runs and the thread goes back to sleep at once — with an async_write the event loop
// would poll (`epoll_wait(0)`) for the completion first, time that sits inside the peer's
// round trip when both share a core (docs/benchmarks.md, "Loop"). What the socket does not
// take, and every write while one is in flight, is coalesced into one buffer for the single
// async_write in flight, so order is kept. Every pending operation holds a shared_ptr to the
// stream, so it outlives them. A close waits at most close_grace for the peer to take what is
// queued, then resets the connection (tcp_stream.hpp).
class TcpStream final : public ByteStream, public std::enable_shared_from_this<TcpStream> {
 public:
  TcpStream(asio::ip::tcp::socket socket, TcpStreamOptions options)
      : socket_(std::move(socket)), options_(options), close_timer_(socket_.get_executor()) {
    error_code error;
    socket_.non_blocking(true, error);   // write_some below must never block
    if (options_.send_buffer_bytes > 0) socket_.set_option(asio::socket_base::send_buffer_size(options_.send_buffer_bytes), error);
    const auto remote = socket_.remote_endpoint(error);
    peer_name_ = error ? std::string("unknown") : remote.address().to_string() + ":" + std::to_string(remote.port());
  }

  void set_handlers(ByteStreamHandlers handlers) override {
    // Shared so a handler may replace the handlers while it runs without destroying itself.
    handlers_ = std::make_shared<const ByteStreamHandlers>(std::move(handlers));
    if (!reading_ && open_) {
      reading_ = true;
      read_next();
    }
  }

  void write(std::string_view bytes) override {
    if (!open_ || bytes.empty()) {
      return;
    }
    if (!writing_) {
      bytes.remove_prefix(write_now(bytes));
      if (bytes.empty()) {
        return;
      }
    }
    pending_.append(bytes);
    if (!writing_) {
      write_pending();
    }
  }

  void close() override {
    if (!open_) {
      return;
    }
    open_ = false;
    // Bytes already accepted by write() still go out, within the grace; the socket closes
    // once they have, or is reset when the grace is over (on_close_grace_over).
    if (writing_) {
      arm_close_timer();
    } else {
      finish_close();
    }
  }

  bool is_open() const override { return open_; }

  // The kernel knows before we read it: after the peer's FIN the socket is in CLOSE_WAIT,
  // after its RST in CLOSE — even while bytes it sent before are still unread.
  bool peer_hung_up() const override {
    if (!open_) return false;
    tcp_info info{};
    socklen_t size = sizeof(info);
    if (::getsockopt(const_cast<asio::ip::tcp::socket&>(socket_).native_handle(), IPPROTO_TCP, TCP_INFO, &info,
                     &size) != 0) {
      return false;
    }
    switch (info.tcpi_state) {
      case TCP_CLOSE_WAIT:
      case TCP_LAST_ACK:
      case TCP_CLOSING:
      case TCP_CLOSE:
        return true;
      default:
        return false;
    }
  }
  std::string peer_name() const override { return peer_name_; }
  std::size_t queued_bytes() const override { return pending_.size() + in_flight_.size(); }

  void set_no_delay(bool enabled) override {
    error_code ignored;
    socket_.set_option(asio::ip::tcp::no_delay(enabled), ignored);
  }

 private:
  void read_next() {
    socket_.async_read_some(asio::buffer(read_buffer_),
                            [self = shared_from_this()](const error_code& error, std::size_t size) {
                              self->on_read(error, size);
                            });
  }

  void on_read(const error_code& error, std::size_t size) {
    if (!open_) {
      return;  // closed locally: nothing more is delivered or reported
    }
    if (error) {
      report_close(error);
      return;
    }
    const auto handlers = handlers_;
    if (handlers->on_bytes) {
      handlers->on_bytes(std::string_view(read_buffer_.data(), size));
    }
    if (open_) {
      read_next();
    }
  }

  // Bytes the socket took at once. An error is left to the async_write of the rest, which
  // meets it again and reports it from the event loop (never from inside the caller's write).
  std::size_t write_now(std::string_view bytes) {
    error_code error;
    const std::size_t sent = socket_.write_some(asio::buffer(bytes.data(), bytes.size()), error);
    return error ? 0 : sent;
  }

  void write_pending() {
    writing_ = true;
    in_flight_.swap(pending_);
    pending_.clear();
    asio::async_write(socket_, asio::buffer(in_flight_),
                      [self = shared_from_this()](const error_code& error, std::size_t) { self->on_written(error); });
  }

  void on_written(const error_code& error) {
    writing_ = false;
    in_flight_.clear();
    if (error) {
      pending_.clear();
      if (open_) {
        report_close(error);
      } else {
        shut_down();
      }
      return;
    }
    if (!pending_.empty()) {
      write_pending();
    } else if (!open_) {
      finish_close();
    }
  }

  // Bytes the kernel holds for the peer (not sent, or not acknowledged yet).
  std::size_t unsent_in_kernel() {
    int bytes = 0;
    if (::ioctl(socket_.native_handle(), SIOCOUTQ, &bytes) != 0 || bytes < 0) return 0;
    return static_cast<std::size_t>(bytes);
  }

  // Closed locally and our queue is empty. With nothing left in the kernel either, the socket
  // closes now; otherwise the peer gets a FIN after the data and the rest of the grace.
  void finish_close() {
    if (shut_down_) {
      return;
    }
    if (unsent_in_kernel() == 0) {
      shut_down();
      return;
    }
    error_code ignored;
    socket_.shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
    arm_close_timer();
  }

  void arm_close_timer() {
    if (close_timer_armed_) {
      return;
    }
    close_timer_armed_ = true;
    close_timer_.expires_after(options_.close_grace);
    close_timer_.async_wait([self = shared_from_this()](const error_code& error) {
      if (!error) {
        self->on_close_grace_over();
      }
    });
  }

  void on_close_grace_over() {
    if (shut_down_) {
      return;
    }
    if (writing_ || unsent_in_kernel() > 0) {
      reset();
    } else {
      shut_down();
    }
  }

  // The peer did not take what we had for it within the grace: RST (SO_LINGER 0) frees the
  // kernel's buffers with the descriptor, and closing cancels our write in flight (its
  // handler frees our queue).
  void reset() {
    shut_down_ = true;
    pending_.clear();
    error_code ignored;
    socket_.set_option(asio::socket_base::linger(true, 0), ignored);
    socket_.close(ignored);
  }

  void report_close(const error_code& error) {
    open_ = false;
    pending_.clear();
    if (!writing_) {
      shut_down();
    }
    const auto handlers = handlers_;
    if (handlers->on_closed) {
      handlers->on_closed(describe_close(error));
    }
  }

  void shut_down() {
    if (shut_down_) {
      return;
    }
    shut_down_ = true;
    if (close_timer_armed_) {
      close_timer_.cancel();
    }
    error_code ignored;
    socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
  }

  static constexpr std::size_t read_buffer_bytes = 64 * 1024;

  asio::ip::tcp::socket socket_;
  TcpStreamOptions options_;
  asio::steady_timer close_timer_;   // the grace of a close with bytes still to go out
  std::string peer_name_;
  std::shared_ptr<const ByteStreamHandlers> handlers_ = std::make_shared<const ByteStreamHandlers>();
  // Not zeroed: only the bytes a read stores are ever looked at, and untouched pages stay out
  // of resident memory (a fleet of small-frame connections would otherwise pay 64 KiB each).
  std::array<char, read_buffer_bytes> read_buffer_;
  std::string in_flight_;
  std::string pending_;
  bool reading_ = false;
  bool writing_ = false;
  bool open_ = true;
  bool shut_down_ = false;
  bool close_timer_armed_ = false;
};

}  // namespace

std::shared_ptr<ByteStream> make_tcp_stream(boost::asio::ip::tcp::socket socket, TcpStreamOptions options) {
  auto stream = std::make_shared<TcpStream>(std::move(socket), options);
  stream->set_no_delay(true);
  return stream;
}

}  // namespace ocp
