#include "world/stream_tap.hpp"

#include <utility>

#include "ocp/executor.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {

// Forwards everything to the wrapped stream; only the inbound byte handler is intercepted.
class StreamTap::Stream final : public ByteStream {
 public:
  Stream(StreamTap& tap, std::shared_ptr<ByteStream> inner) : tap_(tap), inner_(std::move(inner)) {}

  void set_handlers(ByteStreamHandlers handlers) override {
    auto on_bytes = std::move(handlers.on_bytes);
    handlers.on_bytes = [this, on_bytes = std::move(on_bytes)](std::string_view bytes) {
      tap_.observe(bytes);
      if (on_bytes) on_bytes(bytes);
    };
    inner_->set_handlers(std::move(handlers));
  }
  void write(std::string_view bytes) override { inner_->write(bytes); }
  void close() override { inner_->close(); }
  bool is_open() const override { return inner_->is_open(); }
  std::string peer_name() const override { return inner_->peer_name(); }
  void set_no_delay(bool enabled) override { inner_->set_no_delay(enabled); }

 private:
  StreamTap& tap_;
  std::shared_ptr<ByteStream> inner_;
};

std::shared_ptr<ByteStream> StreamTap::wrap(std::shared_ptr<ByteStream> inner) {
  decoder_.reset();  // a new connection starts between frames
  return std::make_shared<Stream>(*this, std::move(inner));
}

void StreamTap::observe(std::string_view bytes) {
  decoder_.put_all(bytes, [this](std::string_view payload) {
    auto decoded = decode_control_message(payload);
    if (!decoded) {
      ++undecodable_frames_;
      return true;
    }
    ++control_messages_;
    last_control_ = std::move(decoded.value());
    last_control_time_ = executor_.now();
    return true;
  });
}

}  // namespace ocp
