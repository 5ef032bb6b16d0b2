// Echo delay added by the reference vehicle client (control frame in → response out).
//
//   BM_VehicleClientEchoLoopback   — over real loopback TCP: the benchmark thread writes a
//       control frame on a blocking socket and reads until the response carrying that pair;
//       the client runs on its own io_context thread (AsioExecutor + make_tcp_stream), exactly
//       as the vehicle_client program does. Includes both kernel loopback traversals and the
//       thread wake-up, so it is an upper bound on what the client adds.
//   BM_VehicleClientEchoInProcess  — the client's own work only: on_bytes → decode → encode
//       → frame → write, on a hand-driven stream.
// Each reports p50_us / p99_us / max_us counters over all iterations. Target: p99 < 100 µs.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <string_view>
#include <thread>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/log.hpp"
#include "ocp/asio/tcp_stream.hpp"
#include "ocp/virtual_executor.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace {

namespace asio = boost::asio;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

// A realistic control message: a live gamepad, telemetry, a little client user data.
std::vector<std::string> control_frames(std::size_t count) {
  ocp::OcpControlMessage message;
  message.controller = ocp::Controller{};
  message.controller->axes.right_trigger = 0.25;
  message.controller->axes.left_x = -0.1;
  message.telemetry.latency_ms = 42;
  message.client_user_data = ocp::RawJson{R"({"mode":"manual","lights":true})"};
  std::vector<std::string> frames;
  std::string payload;
  for (std::size_t index = 0; index < count; ++index) {
    message.ack = ocp::AckPair{(1ull << 53) + 1 + index, static_cast<std::uint32_t>(index * 2654435761u)};
    ocp::encode_control_message(message, payload);
    std::string frame;
    (void)ocp::append_frame(payload, frame);
    frames.push_back(std::move(frame));
  }
  return frames;
}

void report_percentiles(benchmark::State& state, std::vector<double>& samples_us) {
  if (samples_us.empty()) return;
  std::sort(samples_us.begin(), samples_us.end());
  const auto at = [&](double fraction) {
    return samples_us[std::min(samples_us.size() - 1, static_cast<std::size_t>(fraction * samples_us.size()))];
  };
  state.counters["p50_us"] = at(0.50);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = samples_us.back();
}

// Reads one frame from a blocking socket; returns its payload.
std::string read_frame(tcp::socket& socket) {
  char header[ocp::frame_header_bytes];
  asio::read(socket, asio::buffer(header));
  const std::uint32_t length = *ocp::read_length_prefix(std::string_view(header, sizeof(header)));
  std::string payload(length, '\0');
  asio::read(socket, asio::buffer(payload));
  return payload;
}

void BM_VehicleClientEchoLoopback(benchmark::State& state) {
  // Client side: its own io_context thread, like the real program.
  asio::io_context client_io;
  ocp::AsioExecutor executor(client_io);
  ocp::VehicleClient client(executor, ocp::VehicleClientConfig{},
                            ocp::Logger(executor, "vehicle-client", ocp::make_null_sink()));

  // Benchmark side: a blocking "Streamer" socket.
  asio::io_context server_io;
  tcp::acceptor acceptor(server_io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
  tcp::socket client_socket(client_io);
  client_socket.connect(acceptor.local_endpoint());
  tcp::socket server(server_io);
  acceptor.accept(server);
  server.set_option(tcp::no_delay(true));
  client.attach(ocp::make_tcp_stream(std::move(client_socket)));
  std::thread client_thread([&] { client_io.run(); });

  const std::vector<std::string> frames = control_frames(1024);
  std::vector<double> samples_us;
  samples_us.reserve(1 << 20);
  std::size_t index = 0;
  for (auto _ : state) {
    const std::string& frame = frames[index % frames.size()];
    const std::uint64_t expected = (1ull << 53) + 1 + index % frames.size();
    ++index;
    const Clock::time_point start = Clock::now();
    asio::write(server, asio::buffer(frame));
    // Skip keep-alives (only possible after a pause) until our pair comes back.
    for (;;) {
      const ocp::Result<ocp::VehicleResponseMessage> response = ocp::decode_vehicle_response(read_frame(server));
      if (response.ok() && response->ack.ack_time == expected) break;
    }
    const double elapsed_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    state.SetIterationTime(elapsed_us / 1e6);
    samples_us.push_back(elapsed_us);
  }
  report_percentiles(state, samples_us);

  asio::post(client_io, [&] { client.detach(); });
  client_io.stop();
  client_thread.join();
}
BENCHMARK(BM_VehicleClientEchoLoopback)->UseManualTime()->Unit(benchmark::kMicrosecond)->MinTime(3.0);

// A stream that only counts what the client writes.
class CountingStream final : public ocp::ByteStream {
 public:
  void set_handlers(ocp::ByteStreamHandlers handlers) override { handlers_ = std::move(handlers); }
  void write(std::string_view bytes) override { written_bytes += bytes.size(); }
  void close() override {}
  bool is_open() const override { return true; }
  std::string peer_name() const override { return "bench"; }
  void deliver(std::string_view bytes) { handlers_.on_bytes(bytes); }
  std::size_t written_bytes = 0;

 private:
  ocp::ByteStreamHandlers handlers_;
};

void BM_VehicleClientEchoInProcess(benchmark::State& state) {
  ocp::VirtualExecutor executor;
  ocp::VehicleClient client(executor, ocp::VehicleClientConfig{},
                            ocp::Logger(executor, "vehicle-client", ocp::make_null_sink()));
  auto stream = std::make_shared<CountingStream>();
  client.attach(stream);
  const std::vector<std::string> frames = control_frames(1024);
  std::vector<double> samples_us;
  samples_us.reserve(1 << 22);
  std::size_t index = 0;
  for (auto _ : state) {
    const Clock::time_point start = Clock::now();
    stream->deliver(frames[index++ % frames.size()]);
    const double elapsed_us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    state.SetIterationTime(elapsed_us / 1e6);
    samples_us.push_back(elapsed_us);
    // Virtual time advances 10 ms per message, as on the wire, so model ticks happen too.
    executor.run_for(ocp::Micros{10'000});
  }
  benchmark::DoNotOptimize(stream->written_bytes);
  report_percentiles(state, samples_us);
}
BENCHMARK(BM_VehicleClientEchoInProcess)->UseManualTime()->Unit(benchmark::kMicrosecond)->MinTime(1.0);

}  // namespace
