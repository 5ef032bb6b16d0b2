#pragma once
// The side the suite plays, in a World on an AsioExecutor behind a real TCP listening socket
// on 127.0.0.1: for `vehicle` a real StreamerCore (one vehicle, a simulated operator with
// self-echo, no in-process vehicle client); for `operator` the Player, linked to one or several
// vehicles, each a Streamer with the in-process reference client. One host per worker thread;
// it owns its io_context.
//
// The listening socket outlives the Streamers: each case gets a fresh World (new MAC key,
// latency loop from zero, its own ack_time_offset) while a client that stays up across cases
// reconnects to the same port. restart() is the defined Streamer restart a case can ask for:
// the connection is closed, the listening socket is closed and opened anew on the same port,
// and a new World (new CSPRNG MAC key, new latency loop) takes over.
//
// Virtual time (ocp_conformance --time virtual, docs/virtual-time.md): the World runs on a
// VirtualExecutor and the listening socket is a vtime::Controller's; a launched client runs
// under the shim (controller()->environment()) on the same clock, so every wait of a case is
// virtual and exact, and a case takes the wall time the client needs to compute, not to wait.
#include <boost/asio/io_context.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/error.hpp"
#include "ocp/log.hpp"
#include "ocp/asio/tcp_server.hpp"
#include "ocp/virtual_executor.hpp"
#include "streamer/streamer_core.hpp"
#include "vtime/controller.hpp"
#include "world/world.hpp"

namespace ocp::conformance {

// One vehicle the Player is linked to in `ocp_conformance operator` runs.
struct HostedVehicle {
  std::string name;
  bool monitor = false;  // watch-only link (SPEC §7): feedback and video, no control
};

struct StreamerSetup {
  std::uint64_t ack_time_offset = std::uint64_t{1} << 53;  // SPEC §5: conformance uses ≥ 2^53
  bool control_paused = false;                             // paused before any client can connect
  std::size_t write_queue_limit_bytes = 256 * 1024;        // a client that never reads is cut off sooner
  // `ocp_conformance operator`: the port is the Player's :4001 operator API (SPEC §4.2) and the
  // vehicle side is the reference VehicleClient, in-process, so the latency loop turns.
  bool operator_side = false;
  // operator_side only: the vehicles linked to the Player, each with its own Streamer and
  // in-process reference client (a fleet when more than one). Empty: one, host_vehicle_name.
  std::vector<HostedVehicle> fleet;
};

class StreamerHost {
 public:
  explicit StreamerHost(LogSink sink = make_null_sink());
  // Virtual time: the Controller's options (its shim, watchdog, wait trace).
  explicit StreamerHost(const vtime::ControllerOptions& virtual_time, LogSink sink = make_null_sink());
  ~StreamerHost();
  StreamerHost(const StreamerHost&) = delete;
  StreamerHost& operator=(const StreamerHost&) = delete;

  // Binds 127.0.0.1:port (0 = ephemeral). Errors as TcpServer::listen.
  [[nodiscard]] Status listen(std::uint16_t port);
  std::uint16_t port() const { return port_; }

  // A fresh World + Streamer; the previous one (if any) is stopped first.
  [[nodiscard]] Status start_streamer(const StreamerSetup& setup);
  void stop_streamer();
  // Defined restart (see above). Errors: the port could not be bound again.
  [[nodiscard]] Status restart(const StreamerSetup& setup);

  bool has_streamer() const { return world_ != nullptr; }
  StreamerCore& streamer();                          // host_vehicle_name's
  StreamerCore& streamer(std::string_view vehicle);  // a vehicle of the fleet
  std::vector<HostedVehicle> vehicles() const;       // of the running World
  PlayerCore& player();
  bool operator_side() const { return operator_side_; }
  // The client under test is connected (vehicle API or operator API, by the setup).
  bool client_connected();
  // Connections the current Streamer (or Player) accepted from the client, refused ones excluded.
  std::uint64_t client_connections_accepted();
  // The event bus that carries the client's wire (the Streamer's or the Player's).
  EventBus& client_events();
  // The World's clock: wall time since the host started, or virtual time.
  Executor& clock() { return virtual_ ? static_cast<Executor&>(virtual_->executor) : executor_; }
  std::int64_t now_us() const { return (virtual_ ? virtual_->executor.now() : executor_.now()).count(); }
  // Virtual time: the controller a launched client is announced to (its environment, its
  // pid); nullptr in real time.
  vtime::Controller* controller() { return virtual_ ? virtual_->controller.get() : nullptr; }

  // Runs the io_context until `done()` or `timeout` passed; returns done(). Never a sleep.
  // Throws RunInterrupted as soon as the stop check (below) says so.
  bool run_until(const std::function<bool()>& done, std::chrono::milliseconds timeout);
  // Every wait of a case goes through run_until, so this one check lets Ctrl-C cut any case short.
  void stop_when(std::function<bool()> stop_requested) { stop_requested_ = std::move(stop_requested); }
  void run_for(std::chrono::milliseconds duration);

 private:
  struct Virtual {
    VirtualExecutor executor;
    std::unique_ptr<vtime::Controller> controller;
    int listener = -1;
  };
  void on_client_stream(std::shared_ptr<ByteStream> stream);
  bool run_until_virtual(const std::function<bool()>& done, std::chrono::milliseconds timeout);
  bool stop_asked() const { return stop_requested_ && stop_requested_(); }
  std::unique_ptr<Virtual> virtual_;
  boost::asio::io_context io_;
  AsioExecutor executor_;
  LogSink sink_;
  TcpServer server_;
  std::uint16_t port_ = 0;
  std::unique_ptr<World> world_;
  std::vector<HostedVehicle> vehicles_;
  bool operator_side_ = false;
  std::function<bool()> stop_requested_;
};

// The run was interrupted (Ctrl-C) while a case waited: the case has no verdict.
struct RunInterrupted : std::runtime_error {
  RunInterrupted() : std::runtime_error("interrupted") {}
};

inline constexpr const char* host_vehicle_name = "vehicle";

}  // namespace ocp::conformance
