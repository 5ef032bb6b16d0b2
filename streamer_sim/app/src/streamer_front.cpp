#include "streamer_app/streamer_front.hpp"

#include <utility>

namespace ocp {

StreamerFront::StreamerFront(AsioExecutor& executor, World& world, std::string vehicle, Logger logger)
    : world_(world),
      vehicle_(std::move(vehicle)),
      logger_(std::move(logger)),
      server_(executor.io(), [this](std::shared_ptr<ByteStream> stream) {
        ++accepted_;
        logger_.debug("TCP connection from {}", stream->peer_name());
        world_.accept_vehicle_connection(vehicle_, std::move(stream));
      }) {}

Status StreamerFront::listen(const TcpServerOptions& options) {
  if (auto status = server_.listen(options); !status) return status;
  logger_.info("vehicle API listening on {} (vehicle {})", server_.local_address(), vehicle_);
  return Ok{};
}

void StreamerFront::stop() {
  if (!server_.listening()) return;
  logger_.info("vehicle API on {} closed", server_.local_address());
  server_.stop();
}

}  // namespace ocp
