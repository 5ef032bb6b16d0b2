#pragma once
// Plain blocking loopback TCP for the bench's references that must not run through an event
// loop (BareClient, the kernel floor): connect, and send or receive a whole buffer.
#include <cstddef>
#include <cstdint>

namespace ocp::bench {

// A blocking TCP_NODELAY socket connected to 127.0.0.1:port, or -1 (errno says why).
int connect_loopback(std::uint16_t port);
// The whole buffer, or false (peer gone, error, or a receive timeout set on the socket).
bool send_all(int socket, const char* data, std::size_t size);
bool receive_all(int socket, char* data, std::size_t size);

}  // namespace ocp::bench
