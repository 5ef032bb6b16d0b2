#include "timer_client.hpp"

#include <sys/prctl.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "reference_response.hpp"

namespace ocp::bench {

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

class Session {
 public:
  Session(asio::io_context& io, std::uint16_t port) : socket_(io), timer_(io) {
    boost::system::error_code error;
    socket_.connect(tcp::endpoint(asio::ip::address_v4::loopback(), port), error);
    if (error) return;
    socket_.set_option(tcp::no_delay(true), error);
    read();
    next_tick_ = std::chrono::steady_clock::now();
    tick();
  }

 private:
  void read() {
    socket_.async_read_some(asio::buffer(buffer_), [this](boost::system::error_code error, std::size_t size) {
      if (error) {
        timer_.cancel();
        return;
      }
      for_each_control_pair(decoder_, std::string_view(buffer_.data(), size),
                            [this](const AckPair& pair) { newest_ = pair; });
      read();
    });
  }

  void tick() {
    // 10 ms + 10 µs: on one machine the client's clock and the Streamer's are the same, so an
    // exact 10 ms timer would answer at one fixed phase of the tick for the whole run (anything
    // from 0 to 10 ms, decided by start-up). The extra 10 µs sweeps the phase through the whole
    // period every 10 s, as independent clocks do, so the delay is spread over 0–10 ms.
    next_tick_ += std::chrono::microseconds(10'010);
    timer_.expires_at(next_tick_);
    timer_.async_wait([this](boost::system::error_code error) {
      if (error) return;
      if (newest_) answer(*newest_);
      tick();
    });
  }

  void answer(const AckPair& pair) {
    if (!frame_response(pair, payload_, frame_)) return;
    boost::system::error_code error;
    asio::write(socket_, asio::buffer(frame_), error);   // a few hundred bytes: never blocks
  }

  tcp::socket socket_;
  asio::steady_timer timer_;
  std::chrono::steady_clock::time_point next_tick_;
  std::array<char, 8192> buffer_{};
  FrameDecoder decoder_;
  std::optional<AckPair> newest_;
  std::string payload_, frame_;
};

}  // namespace

TimerClient::TimerClient(std::uint16_t port) {
  thread_ = std::thread([this, port] {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    asio::io_context io;
    Session session(io, port);
    while (!stop_) io.run_for(std::chrono::milliseconds(50));
  });
}

void TimerClient::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

}  // namespace ocp::bench
