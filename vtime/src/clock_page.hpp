#pragma once
// The clock page's per-connection delivery counts (vtime/protocol.hpp), the controller's side:
// a woken client thread waits until the bytes counted there have arrived before it looks at
// its sockets.
#include <cstdint>

#include "vtime/protocol.hpp"

namespace ocp::vtime {

// A slot for the connection from `port`: a free one, or the next one round the page. False
// when all max_connections are in use.
bool claim_delivery_slot(ClockPage& page, std::uint16_t port);
void release_delivery_slot(ClockPage& page, std::uint16_t port);
// `total`: the bytes the controller has written to that connection so far.
void publish_delivered(ClockPage& page, std::uint16_t port, std::uint64_t total);

}  // namespace ocp::vtime
