#pragma once
// RecordingStream — a ByteStream the test drives by hand: deliver() calls on_bytes
// synchronously and writes are recorded, so a test can see what the client wrote *during* one
// on_bytes call. (Not a peer: the peers are in tests/support.)
#include <string>
#include <vector>

#include "framed_peer.hpp"
#include "ocp/byte_stream.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

class RecordingStream final : public ByteStream {
 public:
  void set_handlers(ByteStreamHandlers handlers) override { handlers_ = std::move(handlers); }
  void write(std::string_view bytes) override {
    if (open_) written += bytes;
  }
  void close() override { open_ = false; }
  bool is_open() const override { return open_; }
  std::string peer_name() const override { return "recording"; }
  void set_no_delay(bool enabled) override { no_delay = enabled; }

  void deliver(std::string_view bytes) { handlers_.on_bytes(bytes); }
  void peer_close(const std::string& reason) {
    open_ = false;
    handlers_.on_closed(reason);
  }
  // Decodes every complete response written so far.
  std::vector<VehicleResponseMessage> responses() const {
    std::vector<VehicleResponseMessage> result;
    for (const std::string& payload : payloads_of(written)) {
      Result<VehicleResponseMessage> message = decode_vehicle_response(payload);
      if (message.ok()) result.push_back(*message);
    }
    return result;
  }

  std::string written;
  bool no_delay = false;

 private:
  ByteStreamHandlers handlers_;
  bool open_ = true;
};

}  // namespace ocp::testing
