// One rule for a peer that never reads, on both TCP APIs (issue #36: :4000 took about 80 s to
// drop one and :4001 32 s, because the rule was 1 MiB queued and the two ports send at
// different byte rates). Now: a peer that takes none of the bytes waiting for it for 10 s is
// disconnected (peer not reading), on :4000 and :4001 alike — whatever the port sends, however
// many vehicles the Player's frame carries. In virtual time, exactly: 10 s after the first
// frame that found it not reading. The 1 MiB cap stays as the memory bound.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

using testing::frame_of;

struct DeafPeerDrop {
  std::optional<SimTime> first_frame_out;   // the first frame the deaf peer was sent
  std::optional<SimTime> closed_at;
  std::optional<CloseReason> reason;
};

// Keeps sending (so the 2 s read timeout never fires) and never reads.
class NeverReadingPeer {
 public:
  NeverReadingPeer(VirtualExecutor& executor, std::shared_ptr<ByteStream> end, std::string frame)
      : end_(std::move(end)), frame_(std::move(frame)),
        timer_(executor, Micros{500'000}, [this](SimTime) { end_->write(frame_); }) {
    timer_.start(executor.now());
  }

 private:
  std::shared_ptr<ByteStream> end_;   // no handlers: nothing it is sent is ever taken
  std::string frame_;
  PeriodicTimer timer_;
};

struct DeafPeerPort {
  const char* name;
  int vehicles;   // the Player's frame grows with them; the Streamer's control frame does not
};

class NotReadingRule : public ::testing::TestWithParam<DeafPeerPort> {};

TEST_P(NotReadingRule, BothPortsDropADeafPeerTenSecondsAfterItStoppedTaking) {
  WorldConfig config;
  config.player.fleet = GetParam().vehicles > 1;
  for (int v = 0; v < GetParam().vehicles; ++v) {
    VehicleSpec spec = vehicle_spec("truck-" + std::to_string(v + 1));
    spec.in_process_client = v > 0;   // truck-1's vehicle client is the deaf peer
    config.vehicles.push_back(spec);
  }
  VirtualWorld sim(config);
  DeafPeerDrop vehicle_side, operator_side;
  auto watch = sim.world().events().subscribe([&](const Event& event) {
    DeafPeerDrop* drop = nullptr;
    Wire wire{};
    if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
      wire = frame->wire;
      if (frame->direction != FrameDirection::out) return;
      drop = wire == Wire::vehicle ? &vehicle_side : &operator_side;
      if (wire == Wire::vehicle && event.component.name != "truck-1") return;
      if (!drop->first_frame_out) drop->first_frame_out = event.time;
    } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
      if (connection->change != ConnectionChange::closed) return;
      if (connection->wire == Wire::vehicle && event.component.name != "truck-1") return;
      drop = connection->wire == Wire::vehicle ? &vehicle_side : &operator_side;
      if (!drop->closed_at) {
        drop->closed_at = event.time;
        drop->reason = *connection->reason;
      }
    }
  });
  ASSERT_TRUE(sim.start());

  std::string response;
  encode_vehicle_response(VehicleResponseMessage{AckPair{1, 2}, std::nullopt}, response);
  PipeEnds vehicle_pipe = make_pipe(sim.executor());
  sim.world().accept_vehicle_connection("truck-1", vehicle_pipe.b);
  NeverReadingPeer deaf_vehicle(sim.executor(), vehicle_pipe.a, frame_of(response));
  PipeEnds client_pipe = make_pipe(sim.executor());
  sim.world().player().accept_client_connection(client_pipe.a);
  NeverReadingPeer deaf_client(sim.executor(), client_pipe.b, frame_of("{}"));
  sim.run_for(Millis{15'000});

  for (const auto& [side, drop] : {std::pair{":4000 vehicle", &vehicle_side}, std::pair{":4001 client", &operator_side}}) {
    ASSERT_TRUE(drop->first_frame_out.has_value()) << side;
    ASSERT_TRUE(drop->closed_at.has_value()) << side << ": never dropped";
    EXPECT_EQ(drop->reason->code, PeerError::not_reading) << side << ": " << *drop->reason;
    EXPECT_NE(drop->reason->detail.find("took none of the"), std::string::npos) << side << ": " << *drop->reason;
    EXPECT_EQ(*drop->closed_at - *drop->first_frame_out, default_write_stall_timeout)
        << side << ": dropped " << (*drop->closed_at - *drop->first_frame_out).count() << " µs after its first frame";
  }
}

INSTANTIATE_TEST_SUITE_P(Ports, NotReadingRule, ::testing::Values(DeafPeerPort{"one_vehicle", 1}, DeafPeerPort{"a_fleet_of_four", 4}),
                         [](const auto& info) { return std::string(info.param.name); });

// A peer that reads, however slowly its bytes arrive (a 400 ms pipe: 40 frames always in
// flight), is never dropped: it keeps taking.
TEST(NotReadingRule, ASlowButReadingPeerStays) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  PipeOptions slow;
  slow.one_way_delay = Millis{400};
  PipeEnds client_pipe = make_pipe(sim.executor(), slow);
  std::size_t received = 0;
  client_pipe.b->set_handlers({[&](std::string_view bytes) { received += bytes.size(); }, [](const std::string&) {}});
  sim.world().player().accept_client_connection(client_pipe.a);
  PeriodicTimer keep_alive(sim.executor(), Micros{500'000}, [&](SimTime) { client_pipe.b->write(frame_of("{}")); });
  keep_alive.start(sim.now());
  sim.run_for(Millis{30'000});
  EXPECT_TRUE(sim.world().player().client_connected());
  EXPECT_GT(received, 100'000u);
}

}  // namespace
}  // namespace ocp::world_test
