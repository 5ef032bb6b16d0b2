#pragma once
// ByteStream over a connected Boost.Asio TCP socket (real time only). Writes are queued and
// sent in order without blocking; reads are delivered as they arrive. TCP_NODELAY is set.
#include <boost/asio/ip/tcp.hpp>
#include <memory>

#include "ocp/byte_stream.hpp"

namespace ocp {

std::shared_ptr<ByteStream> make_tcp_stream(boost::asio::ip::tcp::socket socket);

}  // namespace ocp
