#pragma once
// World: assembles one Player, one Streamer per vehicle, one fake com channel per vehicle and
// (optionally) an in-process reference vehicle client per vehicle, all on one injected
// Executor. The same World runs in virtual time (VirtualExecutor; see virtual_world.hpp) and in
// real time (AsioExecutor; the simulator executables attach external TCP clients instead).
//
//   World world(executor, config, sink);
//   if (auto status = world.start(); !status) { … status.error().message() … }
//   … drive the executor; change impairments via world.link(name); stall cameras via
//     world.streamer(name); script the gamepad via world.player().gamepad() …
//   world.stop();
//
// Wiring per vehicle (names as in the code):
//   PlayerCore ──OperatorControl, Ping──► ComChannel::to_streamer ──► StreamerCore::handle_link_message
//   StreamerCore ──StreamerFeedback, VideoFrame, Pong──► ComChannel::to_player ──► PlayerCore::handle_link_message
//   StreamerCore ◄══ pipe (ByteStream, framed JSON) ══► VehicleClient      (in_process_client)
//
// Determinism (ARCHITECTURE.md property 3): each component gets its own generator seed derived
// from WorldConfig::seed and a stable component name (see seeds.hpp), so adding a vehicle never
// changes the random draws of another. With deterministic_keys the Streamers' MAC keys are
// derived from the seed as well (virtual-time runs); otherwise each Streamer draws a CSPRNG key.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/com_channel.hpp"
#include "ocp/error.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/executor.hpp"
#include "ocp/log.hpp"
#include "player/player_core.hpp"
#include "streamer/streamer_core.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {

class StreamTap;
class ControlTicker;
class LinkHandover;

struct VehicleSpec {
  std::string name;
  StreamerConfig streamer;                  // streamer.name is set to `name`
  Impairments to_streamer, to_player;       // com-channel impairments per direction
  bool monitor = false;                     // watch-only link (no control from the Player)
  bool in_process_client = true;            // attach the reference VehicleClient over a pipe
  VehicleClientConfig client;
};

struct WorldConfig {
  std::uint64_t seed = 1;
  PlayerConfig player;
  std::vector<VehicleSpec> vehicles;
  // Derive each Streamer's MAC key from `seed` when its StreamerConfig::mac_key is unset.
  // For virtual-time runs (reproducible traces). Real-time runs leave it false: CSPRNG keys.
  bool deterministic_keys = false;
  // Delay before an in-process vehicle client reconnects (through a new pipe) after its
  // connection dropped. Same as the TCP runner's first backoff.
  Micros reconnect_backoff{100'000};
  // One-way delay of the in-process vehicle pipes (a local TCP hop is a few µs; 0 is exact).
  Micros vehicle_pipe_delay{0};
  // Decode what each in-process vehicle client receives (StreamTap), for tests that check
  // what reached the vehicle. Costs one extra decode per control frame; off by default.
  bool tap_vehicle_streams = false;
  // 0: each Streamer ticks on a timer of its own. n ≥ 1: the Streamers of one executor share
  // one ControlTicker (streamer/control_ticker.hpp) whose n slots spread their ticks over the
  // control period (vehicle j in slot j mod n, offset by j mod n · period / n): at fleet scale
  // one task per slot instead of one per vehicle, and no instant where every vehicle is due.
  // With Streamer threads, thread i of t offsets its slots by i/t of a slot: the threads' slots
  // interleave. With one vehicle any value gives the same run as 0.
  std::size_t control_tick_slots = 0;
  // The Player's first frame comes this long after the Streamers start (0: the same instant,
  // so its frames fall on their control ticks). A real operator station's frames have no
  // fixed phase against a vehicle's tick; real-time benchmarks set one so that the operator's
  // frame and the Streamer's handling of it do not run right after every control frame is
  // written, inside the vehicle's round trip (docs/benchmarks.md, "Loop").
  Micros player_phase{0};
};

// A thread the Streamers may live on (real time at fleet scale, see World::set_streamer_threads).
struct StreamerThread {
  using Poster = std::function<void(std::function<void()>)>;
  Executor* executor = nullptr;   // runs on that thread only
  Poster post;                    // thread-safe: runs a task on that thread, soon
};

class World {
 public:
  World(Executor& executor, WorldConfig config, LogSink sink);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Builds links, cores and in-process clients and starts them. Configuration errors (empty
  // or duplicate vehicle names, two vehicles without PlayerConfig::fleet, no vehicle, bad
  // client config, bad Streamer threads) → error, nothing is left running and nothing stays
  // built: once the cause is removed (set_streamer_threads again) start() may be called
  // again. Calling start() after a successful start is an error.
  [[nodiscard]] Status start();
  // Real time on several threads, before start(): vehicle i's Streamer, its vehicle
  // connection and its link's to_player direction live on threads[i % size]; the Player and
  // the to_streamer directions stay on this World's executor. Each link message is handed
  // across by the receiving thread's Poster (`post_to_world` runs a task on this World's
  // thread), so no part is touched by two threads. The caller starts the threads after
  // start() and stops (joins) them before stop(); observe each Streamer on its own bus
  // (streamer(name).events(), on its thread): this World's bus is single-threaded. The
  // LogSink is called from every thread: give a thread-safe one. Not with in-process clients
  // (start() refuses them).
  void set_streamer_threads(std::vector<StreamerThread> threads, StreamerThread::Poster post_to_world);

  // Every event of every part of this world (Player, Streamers, links): each part's bus has
  // this one as its parent. Subscribe before start() to see the very first events.
  EventBus& events() { return events_; }

  // Stops every timer and closes every connection. Safe to call twice; the destructor calls it.
  void stop();
  bool running() const;

  Executor& executor() const;
  const WorldConfig& config() const;
  std::vector<std::string> vehicles() const;   // in configuration order

  PlayerCore& player();
  // The named vehicle's parts. An unknown name is a programming error (asserts, then aborts).
  StreamerCore& streamer(std::string_view vehicle);
  ComChannel& link(std::string_view vehicle);
  VehicleClient* vehicle_client(std::string_view vehicle);   // nullptr when not in-process
  // What the in-process client received (nullptr unless tap_vehicle_streams and in-process).
  const StreamTap* vehicle_tap(std::string_view vehicle) const;

  // An external vehicle client (TCP socket, or a test's raw pipe end) for that vehicle's
  // Streamer. With an in-process client also attached, the Streamer refuses the second one.
  void accept_vehicle_connection(std::string_view vehicle, std::shared_ptr<ByteStream> stream);
  // Drops the in-process client's connection as a broken stream would: the Streamer sees the
  // peer close, the client is detached and reconnects through a new pipe after
  // reconnect_backoff. No-op for a vehicle without an in-process client.
  void drop_vehicle_connection(std::string_view vehicle);
  // The Streamer's side of a close, as a Streamer going away does: it closes the vehicle's
  // connection (any client, in-process or external). With `listener_down` > 0 its vehicle port
  // also refuses connections that long, then listens again on the same port (a restart of the
  // Streamer's listener): an external client's port through the VehicleListener given for it,
  // an in-process client's reconnects by waiting until then.
  void close_vehicle_connection(std::string_view vehicle, Micros listener_down = Micros{0});
  // What stops and restarts the listening socket of a vehicle's external clients (the real-time
  // runner's TcpServer): called with the time it must stay closed. Empty: none.
  using VehicleListener = std::function<void(Micros down)>;
  void set_vehicle_listener(std::string_view vehicle, VehicleListener listener);
  // In-process client connections made so far (1 after start, +1 per reconnect).
  std::uint64_t vehicle_connections(std::string_view vehicle) const;

 private:
  struct Vehicle;
  Vehicle& find(std::string_view vehicle) const;
  // start(), step by step.
  [[nodiscard]] Status check_vehicle_specs() const;
  [[nodiscard]] Status check_streamer_threads() const;
  [[nodiscard]] Status build_vehicles();
  std::unique_ptr<Vehicle> build_vehicle(const VehicleSpec& spec);
  std::unique_ptr<ComChannel> build_link(const VehicleSpec& spec, Executor& streamer_executor);
  std::unique_ptr<StreamerCore> build_streamer(const VehicleSpec& spec, Executor& streamer_executor,
                                               LinkDirection& to_player);
  void build_in_process_client(Vehicle& vehicle);
  void discard_vehicles();
  void create_link_handovers();
  void wire_link_receivers(Vehicle& vehicle);
  void start_parts();
  void connect_in_process_client(Vehicle& vehicle);
  void schedule_reconnect(Vehicle& vehicle);
  ControlTicker& ticker_for(Executor& executor, Micros period);

  Executor& executor_;
  WorldConfig config_;
  LogSink sink_;
  Logger logger_;
  EventBus events_;   // before the parts: they name it as their parent, so it outlives them
  struct Ticker;
  std::vector<std::unique_ptr<Ticker>> tickers_;   // before the parts: their Streamers use them
  std::unique_ptr<PlayerCore> player_;
  std::vector<std::unique_ptr<Vehicle>> vehicles_;
  std::map<std::string, Vehicle*, std::less<>> by_name_;   // find() at fleet scale
  std::vector<StreamerThread> streamer_threads_;           // empty: everything on executor_
  StreamerThread::Poster post_to_world_;
  std::vector<std::unique_ptr<LinkHandover>> handovers_;   // one per Streamer thread
  std::unique_ptr<LinkHandover> to_world_;
  Executor::TimerId player_start_timer_ = 0;   // WorldConfig::player_phase
  bool started_ = false;
  std::atomic<bool> running_ = false;   // read by the link hand-overs on the Streamer threads
};

}  // namespace ocp
