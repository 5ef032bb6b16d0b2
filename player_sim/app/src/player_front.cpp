#include "player_app/player_front.hpp"

#include <utility>

namespace ocp {

PlayerFront::PlayerFront(AsioExecutor& executor, World& world, Logger logger)
    : world_(world),
      logger_(std::move(logger)),
      server_(executor.io(), [this](std::shared_ptr<ByteStream> stream) {
        ++accepted_;
        logger_.debug("TCP connection from {}", stream->peer_name());
        world_.player().accept_client_connection(std::move(stream));
      }) {}

Status PlayerFront::listen(const TcpServerOptions& options) {
  if (auto status = server_.listen(options); !status) return status;
  logger_.info("operator API listening on {}", server_.local_address());
  return Ok{};
}

void PlayerFront::stop() {
  if (!server_.listening()) return;
  logger_.info("operator API on {} closed", server_.local_address());
  server_.stop();
}

}  // namespace ocp
