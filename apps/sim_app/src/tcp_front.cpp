#include "sim_app/tcp_front.hpp"

#include <utility>

namespace ocp::sim_app {

TcpFront::TcpFront(AsioExecutor& executor, std::string api, std::string detail, Accept accept, Logger logger)
    : api_(std::move(api)),
      detail_(std::move(detail)),
      accept_(std::move(accept)),
      logger_(std::move(logger)),
      server_(executor.io(), [this](std::shared_ptr<ByteStream> stream) {
        ++accepted_;
        logger_.debug("TCP connection from {}", stream->peer_name());
        accept_(std::move(stream));
      }) {}

Status TcpFront::listen(const TcpServerOptions& options) {
  if (auto status = server_.listen(options); !status) return status;
  logger_.info("{} listening on {}{}{}", api_, server_.local_address(), detail_.empty() ? "" : " ", detail_);
  return Ok{};
}

void TcpFront::stop() {
  if (!server_.listening()) return;
  logger_.info("{} on {} closed", api_, server_.local_address());
  server_.stop();
}

std::unique_ptr<TcpFront> vehicle_api_front(AsioExecutor& executor, World& world, std::string vehicle, Logger logger) {
  // Quoted: streamer_sim's default vehicle is called "vehicle", and "(vehicle vehicle)" read
  // like a typo.
  std::string detail = "for vehicle '" + vehicle + "'";
  return std::make_unique<TcpFront>(
      executor, "vehicle API", std::move(detail),
      [&world, vehicle = std::move(vehicle)](std::shared_ptr<ByteStream> stream) {
        world.accept_vehicle_connection(vehicle, std::move(stream));
      },
      std::move(logger));
}

std::unique_ptr<TcpFront> operator_api_front(AsioExecutor& executor, World& world, Logger logger) {
  return std::make_unique<TcpFront>(
      executor, "operator API", "",
      [&world](std::shared_ptr<ByteStream> stream) { world.player().accept_client_connection(std::move(stream)); },
      std::move(logger));
}

}  // namespace ocp::sim_app
