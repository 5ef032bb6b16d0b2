#include "bare_client.hpp"

#include <sys/prctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <string>

#include "blocking_socket.hpp"
#include "reference_response.hpp"

namespace ocp::bench {

BareClient::BareClient(std::uint16_t port) {
  const int socket = connect_loopback(port);
  if (socket < 0) return;   // no answers: the report shows a reference with no echoes
  socket_ = socket;
  thread_ = std::thread([socket] {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);   // as the Streamer's thread
    std::array<char, 16384> buffer{};
    FrameDecoder decoder;
    std::string payload, frame;
    bool open = true;
    while (open) {
      const ssize_t size = ::read(socket, buffer.data(), buffer.size());
      if (size <= 0) break;
      for_each_control_pair(decoder, std::string_view(buffer.data(), static_cast<std::size_t>(size)),
                            [&](const AckPair& pair) {
                              if (open && frame_response(pair, payload, frame)) open = send_all(socket, frame.data(), frame.size());
                            });
    }
  });
}

void BareClient::stop() {
  const int socket = socket_.exchange(-1);
  if (socket < 0) return;
  ::shutdown(socket, SHUT_RDWR);   // the blocked read returns 0
  if (thread_.joinable()) thread_.join();
  ::close(socket);
}

}  // namespace ocp::bench
