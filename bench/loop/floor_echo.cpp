#include "floor_echo.hpp"

#include <sys/prctl.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <string>

namespace ocp::bench {

namespace asio = boost::asio;
using asio::ip::tcp;

FloorEcho::FloorEcho(std::chrono::steady_clock::time_point first_send) {
  thread_ = std::thread([this, first_send] {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);   // as the Streamer's thread
    asio::io_context io;
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
    tcp::socket echo_side(io);
    echo_side.connect(acceptor.local_endpoint());
    tcp::socket sender(io);
    acceptor.accept(sender);
    sender.set_option(tcp::no_delay(true));
    echo_side.set_option(tcp::no_delay(true));
    std::thread echo([&echo_side] {
      prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
      std::array<char, 4096> buffer{};
      boost::system::error_code error;
      for (;;) {
        const std::size_t size = echo_side.read_some(asio::buffer(buffer), error);
        if (error) return;
        asio::write(echo_side, asio::buffer(buffer.data(), size), error);
        if (error) return;
      }
    });
    const std::string frame(380, 'x');   // about a control frame
    std::string reply(frame.size(), '\0');
    auto deadline = first_send;
    boost::system::error_code error;
    for (; !stop_; deadline += std::chrono::milliseconds(10)) {
      std::this_thread::sleep_until(deadline);
      const auto sent_at = std::chrono::steady_clock::now();
      asio::write(sender, asio::buffer(frame), error);
      if (!error) asio::read(sender, asio::buffer(reply), error);
      if (error) break;
      round_trips_us_.push_back(
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - sent_at).count());
    }
    sender.shutdown(tcp::socket::shutdown_both, error);
    echo.join();
  });
}

void FloorEcho::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

}  // namespace ocp::bench
