#pragma once
// ByteStream over a connected Boost.Asio TCP socket (real time only). Writes are queued and
// sent in order without blocking; reads are delivered as they arrive. TCP_NODELAY is set.
//
// close() releases the socket within a bounded time, whatever the peer does (as nginx's
// send_timeout + reset_timedout_connection): bytes already accepted by write() get
// `close_grace` to go out; a peer that has not taken them by then (it stopped reading) is
// reset — SO_LINGER 0, RST — so our queue, the kernel's buffers and the descriptor are freed
// instead of waiting for the peer to leave.
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <memory>

#include "ocp/byte_stream.hpp"

namespace ocp {

struct TcpStreamOptions {
  std::chrono::milliseconds close_grace{1000};
  // SO_SNDBUF, when > 0 (0: the kernel's, which grows to 4 MB). A server's streams take a
  // small one (TcpServerOptions): then a peer that never reads fills the kernel's buffers in
  // seconds on either API, and the not-reading rule (framed_connection.hpp), which counts
  // from the moment our own queue holds bytes, drops it after about the same time on both.
  int send_buffer_bytes = 0;
};

std::shared_ptr<ByteStream> make_tcp_stream(boost::asio::ip::tcp::socket socket, TcpStreamOptions options = {});

}  // namespace ocp
