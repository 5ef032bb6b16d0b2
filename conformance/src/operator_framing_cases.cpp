// `ocp_conformance operator`, framing of what the Player sends (SPEC §2 on :4001): the
// client must read VehicleOcpShared frames split into pieces, several coalesced in one write,
// and skip an oversized one, and keep returning the right pairs. The Player's own output is
// paused while hand-made frames go out (PlayerCore::write_raw_to_client), so nothing lands
// between the pieces; each frame carries its own pair, so what came back tells what was read.
#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/json_codec.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance {
namespace detail {

// The Player's latest VehicleOcpShared with the hosted vehicle's pair replaced by `pair`: a
// frame the client cannot tell from a real one, but whose return is unmistakable.
std::string shared_frame(CaseContext& context, const AckPair& pair, const std::function<void(VehicleOcpShared&)>& shape,
                         bool unknown_fields) {
  VehicleOcpShared shared = context.host().player().last_shared();
  shared.vehicle_feedback[host_vehicle_name].ack = pair;
  if (shape) shape(shared);
  std::string json;
  encode_vehicle_ocp_shared(shared, json);
  if (unknown_fields) {
    // Forward compatibility (SPEC §2): a field a later product adds, at top level and in the entry.
    const std::string entry = std::string("\"") + host_vehicle_name + "\":{";
    if (const auto at = json.find(entry); at != std::string::npos)
      json.insert(at + entry.size(), R"("x_future_metric":{"p99":[1.5,null]},)");
    json.insert(1, R"("protocol_revision":"2099.1",)");
  }
  return frame_bytes(json);
}

// Connected, settled, and the Player's own output paused; false (and `outcome` set) if not.
bool ready_for_crafted(CaseContext& context, Outcome& outcome) {
  context.run_for(milliseconds(300));
  context.host().player().set_client_output_paused(true);
  context.run_for(milliseconds(20));  // answers to the last real frames arrive
  if (context.host().player().client_connected()) return true;
  outcome = failed("the connection closed before the hand-made frames were sent");
  return false;
}

bool returned_since(const OperatorObservations& observed, const AckPair& pair, std::int64_t since_us) {
  const auto found = observed.returned.find(host_vehicle_name);
  if (found == observed.returned.end()) return false;
  for (const SentPair& back : found->second) {
    if (back.time_us >= since_us && back.ack == pair) return true;
  }
  return false;
}

// Writes `bytes` cut at `cuts`, pieces `gap` apart, and waits (bounded) until the last piece is
// out, so the next write can never land between the pieces on a slow machine.
void write_in_pieces(CaseContext& context, const std::string& bytes, const std::vector<std::size_t>& cuts,
                     milliseconds gap) {
  PlayerCore& player = context.host().player();
  const std::uint64_t target = player.stats().client_bytes_out + bytes.size();
  if (!player.write_raw_to_client(bytes, cuts, gap)) return;
  context.wait_until([&] { return !player.client_connected() || player.stats().client_bytes_out >= target; },
                     milliseconds(5000));
}

// The common verdict: connection kept since `start_us`, every pair in `required` returned,
// no pair returned that the Player never published.
Outcome grade_crafted_shared(CaseContext& context, std::int64_t start_us, const std::vector<AckPair>& sent,
                             const std::vector<AckPair>& required, const std::string& what) {
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  std::size_t returned = 0;
  for (const AckPair& p : sent) returned += returned_since(observed, p, start_us);
  const std::string counts = fmt::format("{}; {} of their {} pairs returned", what, returned, sent.size());
  for (std::size_t i = 0; i < observed.closed_us.size(); ++i) {
    if (observed.closed_us[i] >= start_us)
      return failed(counts + "; the connection closed: " + observed.close_codes[i]);
  }
  const PairReturns returns = pair_returns(observed, host_vehicle_name);
  if (!returns.altered.empty()) {
    std::vector<AckPair> all = returns.published;
    all.insert(all.end(), sent.begin(), sent.end());  // hand-made frames' pairs too
    return failed_with_cause(counts + "; returned pairs never published: " + list_pairs(returns.altered),
                             returns.altered, all);
  }
  for (const AckPair& p : required) {
    if (!returned_since(observed, p, start_us)) return failed(counts + "; never returned: " + describe(p));
  }
  return ok(counts + "; connection kept");
}

}  // namespace detail

namespace {

using namespace detail;

Outcome split_frames(CaseContext& context) {
  Outcome outcome;
  if (!ready_for_crafted(context, outcome)) return outcome;
  PlayerCore& player = context.host().player();
  const std::int64_t start = context.now_us();
  std::vector<AckPair> sent;
  // One frame dribbled byte by byte, 1 ms apart.
  sent.push_back(crafted_pair(51, 0));
  const std::string whole = shared_frame(context, sent.back(), {}, false);
  std::vector<std::size_t> every;
  for (std::size_t k = 1; k < whole.size(); ++k) every.push_back(k);
  write_in_pieces(context, whole, every, milliseconds(1));
  context.run_for(milliseconds(50));  // time to answer it, even on a 10 ms timer
  // Frames cut inside the length prefix, at its end, inside the payload and before the last
  // byte (one frame at all of them), the pieces 5 ms apart.
  const std::size_t n = whole.size();
  const std::vector<std::vector<std::size_t>> cuts{{1}, {2}, {3}, {4}, {5}, {n / 2}, {n - 1}, {2, 4, n / 2, n - 1}};
  for (const auto& at : cuts) {
    if (!player.client_connected()) break;
    sent.push_back(crafted_pair(52, sent.size()));
    write_in_pieces(context, shared_frame(context, sent.back(), {}, false), at, milliseconds(5));
    context.run_for(milliseconds(20));
  }
  context.run_for(milliseconds(200));
  return grade_crafted_shared(
      context, start, sent, {sent.front(), sent.back()},
      fmt::format("a {}-byte frame sent byte by byte, then {} frames cut at chosen offsets", n, sent.size() - 1));
}

Outcome coalesced_frames(CaseContext& context) {
  Outcome outcome;
  if (!ready_for_crafted(context, outcome)) return outcome;
  PlayerCore& player = context.host().player();
  const std::int64_t start = context.now_us();
  std::vector<AckPair> sent, lasts;
  for (std::size_t write = 0; write < 3 && player.client_connected(); ++write) {
    std::string segment;
    for (std::size_t i = 0; i < 20; ++i) {
      sent.push_back(crafted_pair(61 + write, i));
      segment += shared_frame(context, sent.back(), {}, false);
    }
    lasts.push_back(sent.back());
    (void)player.write_raw_to_client(segment);
    context.run_for(milliseconds(150));
  }
  context.run_for(milliseconds(150));
  return grade_crafted_shared(context, start, sent, lasts,
                              "3 writes of 20 frames each (the last pair of each must be returned)");
}

Outcome oversized_frame_skipped(CaseContext& context) {
  Outcome outcome;
  if (!ready_for_crafted(context, outcome)) return outcome;
  PlayerCore& player = context.host().player();
  const std::int64_t start = context.now_us();
  context.note("writing a 20000-byte VehicleOcpShared frame (over the 16 KiB limit)");
  (void)player.write_raw_to_client(oversized_frame(20000));
  context.run_for(milliseconds(20));
  std::vector<AckPair> sent;
  for (std::size_t i = 0; i < 10 && player.client_connected(); ++i) {
    sent.push_back(crafted_pair(71, i));
    (void)player.write_raw_to_client(shared_frame(context, sent.back(), {}, false));
    context.run_for(milliseconds(10));
  }
  context.run_for(milliseconds(300));
  // Nothing sent when the client dropped the connection at once: grade() reports the close.
  const std::vector<AckPair> last = sent.empty() ? std::vector<AckPair>{} : std::vector<AckPair>{sent.back()};
  return beyond_what_the_product_sends(
      grade_crafted_shared(context, start, sent, last, fmt::format("a 20000-byte frame, then {} frames", sent.size())));
}

}  // namespace

void add_operator_framing_cases(std::vector<VehicleCase>& cases) {
  const StreamerSetup op = operator_setup();
  cases.push_back(
      {{{"operator/2/3",
         "VehicleOcpShared frames split into pieces",
         "SPEC §2, §4.2",
         "§2 (both TCP APIs, both directions): \"Frame = uint32 little-endian payload length, then that many bytes of "
         "UTF-8 JSON.\" — Player TCP server: \"same bind rule and framing as §2\" (TCP is a byte stream: a frame "
         "may arrive in any number of pieces)",
         Tier::must,
         milliseconds(10'000),
         {"OK: a frame written byte by byte and frames cut inside the length prefix, after it, inside the payload "
          "and before its last byte are all read; the first and last pairs returned; connection kept"},
         "broken_client.py op-naive-recv"},
        split_frames},
       op});
  cases.push_back(
      {{{"operator/2/4",
         "several VehicleOcpShared frames coalesced in one write",
         "SPEC §2, §4.2",
         "§2 (both TCP APIs, both directions): \"Frame = uint32 little-endian payload length, then that many bytes of "
         "UTF-8 JSON.\" — Player TCP server: \"same bind rule and framing as §2\" (several frames may arrive in "
         "one read)",
         Tier::must,
         milliseconds(10'000),
         {"OK: 20 frames written at once are all read; the latest pair of each write is returned; connection kept"},
         "broken_client.py op-naive-recv"},
        coalesced_frames},
       op});
  cases.push_back(
      {{{"operator/2/5",
         "skips an oversized VehicleOcpShared frame, keeps the connection",
         "SPEC §2, §4.2",
         "\"Inbound frame larger than that: read and discard (drain) exactly length bytes, log a warning, keep the "
         "connection.\" — Player TCP server: \"same bind rule and framing as §2\"",
         Tier::should,
         milliseconds(10'000),
         {"OK: after a 20000-byte frame the client stays connected and returns the following frames' pairs",
          "NON-STRICT: the client closes or stops returning pairs after it (the product never sends such a frame: SPEC "
          "§2 Decision)"},
         "broken_client.py op-reject-oversized (NON-STRICT)"},
        oversized_frame_skipped},
       op});
}

}  // namespace ocp::conformance
