#include "bare_client.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <string>

#include "reference_response.hpp"

namespace ocp::bench {

namespace {

bool write_all(int socket, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t written = ::send(socket, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (written <= 0) return false;
    done += static_cast<std::size_t>(written);
  }
  return true;
}

}  // namespace

BareClient::BareClient(std::uint16_t port) {
  const int socket = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (socket < 0) return;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const int one = 1;
  if (::connect(socket, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
      ::setsockopt(socket, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) != 0) {
    ::close(socket);
    return;   // no answers: the report shows a reference with no echoes
  }
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
                              if (open && frame_response(pair, payload, frame)) open = write_all(socket, frame);
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
