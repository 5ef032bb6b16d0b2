#pragma once
// One direction of the com channel between a Player and a Streamer, as the cores see it: a
// sender of LinkMessage values and, at the other end, a receiver. The cores hold a Link and
// nothing else of the channel, so any of its implementations plugs in:
//  * LinkDirection (ocp/com_channel.hpp, target ocp_link): the in-process fake channel, with
//    its impairments (delay, loss, traces, recordings), in virtual or real time;
//  * UdpComEndpoint (sim_app/udp_com.hpp): the channel over UDP between two hosts.
// As ByteStream has Pipe beside TcpStream, Link has LinkDirection beside UdpComEndpoint.
#include <functional>
#include <utility>

#include "ocp/link_messages.hpp"

namespace ocp {

class Link {
 public:
  using Receiver = std::function<void(LinkMessage&&)>;
  virtual ~Link() = default;
  // Hands `message` to the channel; it reaches the receiver later, or never (a lossy channel).
  // Never calls back into the sender synchronously.
  virtual void send(LinkMessage message) = 0;
  // Who gets what crosses this direction; replaces the previous receiver.
  virtual void set_receiver(Receiver receiver) = 0;
};

// A receiver that sends on to `next`: chains two links, as the apps chain the simulated
// direction (impairments at the sender) into the UDP one. `next` must outlive the receiver.
inline Link::Receiver forward_to(Link& next) {
  return [&next](LinkMessage&& message) { next.send(std::move(message)); };
}

}  // namespace ocp
