// NagleModel (vtime/nagle.hpp): Linux's Nagle algorithm on one OCP connection in virtual time.
// A split write (a 4-byte length prefix, then the payload) without TCP_NODELAY has its payload
// held exactly until we write to the client or 40 ms pass; one write per frame, or
// TCP_NODELAY, is never held.
#include <gtest/gtest.h>

#include "vtime/nagle.hpp"

namespace {

using ocp::SimTime;
using ocp::vtime::NagleModel;

constexpr SimTime at_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

TEST(VirtualTimeNagleModel, ASplitWriteHoldsThePayloadUntilOurNextWrite) {
  NagleModel nagle;
  // The prefix (4 bytes) and the payload (96) at one instant: the prefix goes, the payload waits.
  EXPECT_EQ(nagle.arrived(100, 4, false, at_ms(0)), 4u);
  EXPECT_EQ(nagle.held(), 96u);
  EXPECT_EQ(nagle.delayed_ack_due(), at_ms(40));
  // Our next frame, 7 ms later, carries the ACK: the payload goes then, and is in flight.
  EXPECT_EQ(nagle.acknowledged(at_ms(7)), 100u);
  EXPECT_EQ(nagle.delayed_ack_due(), at_ms(47));
  // The next split write finds the payload unacknowledged: all of it waits.
  EXPECT_EQ(nagle.arrived(200, 104, false, at_ms(7)), 100u);
  EXPECT_EQ(nagle.acknowledged(at_ms(20)), 200u);
}

TEST(VirtualTimeNagleModel, WithoutOurWriteTheDelayedAckReleasesAfter40Ms) {
  NagleModel nagle;
  EXPECT_EQ(nagle.arrived(100, 4, false, at_ms(5)), 4u);
  EXPECT_EQ(nagle.delayed_ack_due(), at_ms(45));
  EXPECT_EQ(nagle.acknowledged(at_ms(45)), 100u);   // the controller's delayed-ACK event
  EXPECT_EQ(nagle.delayed_ack_due(), at_ms(85));
  EXPECT_EQ(nagle.acknowledged(at_ms(85)), 100u);   // nothing held: nothing more in flight
  EXPECT_EQ(nagle.delayed_ack_due(), std::nullopt);
}

TEST(VirtualTimeNagleModel, OneWritePerFrameGoesAtOnceWhenNothingIsInFlight) {
  NagleModel nagle;
  EXPECT_EQ(nagle.arrived(100, 100, false, at_ms(0)), 100u);
  EXPECT_EQ(nagle.acknowledged(at_ms(10)), 100u);   // our next frame
  EXPECT_EQ(nagle.arrived(200, 200, false, at_ms(10)), 200u);
  EXPECT_EQ(nagle.held(), 0u);
}

// Linux sends full-sized segments whatever is in flight; only the small rest waits. So the
// Controller never holds more than one MSS of a connection.
TEST(VirtualTimeNagleModel, FullSizedSegmentsGoAndLessThanOneMssIsHeld) {
  NagleModel nagle;
  constexpr std::uint64_t mss = NagleModel::loopback_mss;
  EXPECT_EQ(nagle.arrived(4 + 3 * mss + 100, 4, false, at_ms(0)), 4 + 3 * mss);
  EXPECT_EQ(nagle.held(), 100u);
  EXPECT_EQ(nagle.delayed_ack_due(), at_ms(40));   // the prefix's: still the small segment in flight
  EXPECT_EQ(nagle.acknowledged(at_ms(5)), 4 + 3 * mss + 100);
}

TEST(VirtualTimeNagleModel, TcpNoDelayNeverHolds) {
  NagleModel nagle;
  EXPECT_EQ(nagle.arrived(100, 4, true, at_ms(0)), 100u);
  EXPECT_EQ(nagle.arrived(200, 104, true, at_ms(0)), 200u);
  EXPECT_EQ(nagle.delayed_ack_due(), std::nullopt);   // no ACK awaited, no event scheduled
}

TEST(VirtualTimeNagleModel, SettingTcpNoDelayPushesWhatIsHeld) {
  NagleModel nagle;
  EXPECT_EQ(nagle.arrived(100, 4, false, at_ms(0)), 4u);
  EXPECT_EQ(nagle.arrived(100, 0, true, at_ms(3)), 100u);
}

TEST(VirtualTimeNagleModel, BytesWithoutAReportedWriteGoAsOneWriteAndACloseSendsAll) {
  NagleModel nagle;
  EXPECT_EQ(nagle.arrived(50, 0, false, at_ms(0)), 50u);   // a sweep found them: one write
  EXPECT_EQ(nagle.arrived(80, 60, false, at_ms(1)), 50u);  // held behind the first
  EXPECT_EQ(nagle.closed(), 80u);
  EXPECT_EQ(nagle.held(), 0u);
}

}  // namespace
