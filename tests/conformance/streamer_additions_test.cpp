// The StreamerCore additions the conformance suite uses (streamer_core.hpp, "Conformance
// testing"), in virtual time over a pipe: paused output, raw / hand-cut frames, server close.
#include <gtest/gtest.h>

#include "../streamer/streamer_harness.hpp"
#include "conformance/control_frames.hpp"

namespace ocp::streamer_test {
namespace {

TEST(StreamerConformanceHooks, PausedOutputSendsNoControlFramesButTicksGoOn) {
  StreamerHarness h;
  h.core.start();
  TestVehicle& vehicle = h.connect_vehicle();
  h.executor.run_for(ms(100));
  const std::size_t before = vehicle.received.size();
  EXPECT_GE(before, 9u);
  h.core.set_control_output_paused(true);
  EXPECT_TRUE(h.core.control_output_paused());
  const auto ticks = h.core.stats().control_ticks;
  h.executor.run_for(ms(500));
  EXPECT_EQ(vehicle.received.size(), before);
  EXPECT_GE(h.core.stats().control_ticks, ticks + 49);   // faults still evaluated
  h.core.set_control_output_paused(false);
  h.executor.run_for(ms(50));
  EXPECT_GT(vehicle.received.size(), before);
}

TEST(StreamerConformanceHooks, RawFrameInPiecesArrivesWholeAfterTheLastPiece) {
  StreamerHarness h;
  h.core.start();
  TestVehicle& vehicle = h.connect_vehicle();
  h.core.set_control_output_paused(true);
  h.executor.run_for(ms(5));
  const conformance::CraftedControl control{AckPair{~std::uint64_t{0}, 0xFFFFFFFFu}};
  const std::string frame = conformance::frame_bytes(conformance::control_payload(control));
  std::uint32_t published_prefix = 0;
  std::optional<AckPair> published_pair;
  auto subscription = h.core.events().subscribe([&](const Event& event) {
    if (const auto* wire = std::get_if<WireFrame>(&event.body); wire && wire->direction == FrameDirection::out) {
      published_prefix = wire->length_prefix;
      published_pair = wire->ack;
    }
  });
  const SimTime start = h.executor.now();
  ASSERT_TRUE(h.core.write_raw_to_vehicle(frame, {1, 3, 10}, Micros{2000}).ok());
  EXPECT_EQ(published_prefix, frame.size() - 4);   // one WireFrame for the whole frame
  ASSERT_TRUE(published_pair.has_value());
  EXPECT_EQ(published_pair->ack_time, ~std::uint64_t{0});
  h.executor.run_for(ms(5));
  EXPECT_TRUE(vehicle.received.empty());   // last piece due at +6 ms
  h.executor.run_for(ms(2));
  ASSERT_EQ(vehicle.received.size(), 1u);
  EXPECT_EQ(vehicle.received[0].ack, control.ack);
  EXPECT_GE(vehicle.received_at[0] - start, Micros{6000});
}

TEST(StreamerConformanceHooks, OversizedRawFrameIsWrittenAsIs) {
  StreamerHarness h;
  h.core.start();
  h.connect_vehicle();
  h.core.set_control_output_paused(true);
  h.executor.run_for(ms(5));
  const auto out_before = h.core.stats().vehicle_bytes_out;
  ASSERT_TRUE(h.core.write_raw_to_vehicle(conformance::oversized_frame(20000)).ok());
  EXPECT_EQ(h.core.stats().vehicle_bytes_out - out_before, 20004u);
}

TEST(StreamerConformanceHooks, RawWriteWithoutVehicleFails) {
  StreamerHarness h;
  h.core.start();
  const Status status = h.core.write_raw_to_vehicle("abcd");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, make_error_code(LocalError::not_connected));
}

TEST(StreamerConformanceHooks, CloseVehicleConnectionClosesFromTheServerSide) {
  StreamerHarness h;
  h.core.start();
  TestVehicle& vehicle = h.connect_vehicle();
  h.executor.run_for(ms(20));
  h.core.close_vehicle_connection();
  h.executor.run_for(ms(1));
  EXPECT_FALSE(h.core.vehicle_connected());
  EXPECT_TRUE(vehicle.closed_by_peer());
  ASSERT_TRUE(h.core.stats().last_close_reason.has_value());
  EXPECT_EQ(h.core.stats().last_close_reason->code, make_error_code(LocalError::shut_down));
  h.core.close_vehicle_connection();   // no-op without a vehicle
}

}  // namespace
}  // namespace ocp::streamer_test
