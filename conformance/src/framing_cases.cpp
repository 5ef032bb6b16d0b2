// Framing (SPEC §2, seed 000 "Message framing"): valid responses, robust reading of split,
// coalesced and oversized control frames, responses while control pauses.
#include <algorithm>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

Outcome valid_responses(CaseContext& context) {
  context.run_for(milliseconds(1000));
  const Observations observed = Observations::from(context.entries());
  std::size_t drained = 0, valid = 0;
  std::uint32_t largest = 0;
  for (const Response& response : observed.all_responses) {  // a rule for every frame, in the window or not
    drained += response.drained;
    valid += response.ack.has_value();
    largest = std::max(largest, response.length_prefix);
  }
  const std::string counts =
      fmt::format("{} responses: {} valid, {} oversized (drained), largest length prefix {} bytes",
                  observed.all_responses.size(), valid, drained, largest);
  if (observed.closed_by_peer_error())
    return failed(counts + "; the Streamer closed the connection: " + last_close(observed));
  if (drained > 0) return failed(counts);
  if (valid < 10) return failed(counts + "; fewer than 10 valid responses in 1 s");
  return ok(counts);
}

Outcome split_frames(CaseContext& context) {
  context.run_for(milliseconds(200));
  context.streamer().set_control_output_paused(true);
  const std::int64_t start = context.now_us();
  const std::size_t closes_before = Observations::from(context.entries()).closed_us.size();
  if (!context.streamer().vehicle_connected()) {
    return failed("the connection closed before the split frames were sent: " +
                  last_close(Observations::from(context.entries())));
  }
  std::vector<AckPair> pairs;
  // (a) One frame dribbled byte by byte, 1 ms apart.
  CraftedControl dribbled{crafted_pair(21, 0)};
  dribbled.client_user_data = R"({"mode":"manual"})";
  const std::string whole = frame_bytes(control_payload(dribbled));
  std::vector<std::size_t> every;
  for (std::size_t k = 1; k < whole.size(); ++k) every.push_back(k);
  pairs.push_back(dribbled.ack);
  // Each frame's pieces must all be out before the next frame starts: bytes_out tells.
  const auto written = [&](std::uint64_t target) {
    return [&context, target] {
      return !context.streamer().vehicle_connected() || context.streamer().stats().vehicle_bytes_out >= target;
    };
  };
  std::uint64_t target = context.streamer().stats().vehicle_bytes_out + whole.size();
  (void)context.streamer().write_raw_to_vehicle(whole, every, milliseconds(1));
  context.wait_until(written(target), milliseconds(5000));
  context.run_for(milliseconds(50));  // time to answer it, even on a 10 ms timer
  const AckPair dribbled_pair = dribbled.ack;
  // (b) For every boundary k: one frame cut in two at k, the pieces 1 ms apart.
  std::size_t frame_size = 0;
  for (std::size_t k = 1;; ++k) {
    if (!context.streamer().vehicle_connected()) break;
    CraftedControl control{crafted_pair(22, k)};
    control.client_user_data = R"({"mode":"manual"})";
    const std::string frame = frame_bytes(control_payload(control));
    frame_size = frame.size();
    if (k >= frame.size()) break;
    pairs.push_back(control.ack);
    target = context.streamer().stats().vehicle_bytes_out + frame.size();
    (void)context.streamer().write_raw_to_vehicle(frame, {k}, milliseconds(1));
    context.wait_until(written(target), milliseconds(1000));
    context.run_for(milliseconds(1));
  }
  context.run_for(milliseconds(300));
  const Observations observed = Observations::from(context.entries());
  std::size_t echoed = 0;
  for (const AckPair& p : pairs) echoed += first_echo(observed, p, start) != nullptr;
  const auto unknown = unknown_pairs(observed, start, pairs);
  const bool closed = observed.closed_us.size() > closes_before;
  const std::string counts =
      fmt::format("a {}-byte frame sent byte by byte, then {} frames cut at every boundary; {} of {} pairs echoed",
                  frame_size, pairs.size() - 1, echoed, pairs.size());
  if (closed) return failed(counts + "; connection closed: " + last_close(observed));
  if (!unknown.empty())
    return failed_over_altered_pairs(counts + "; echoed pairs never sent: " + list_pairs(unknown), unknown, observed,
                                     pairs);
  if (!first_echo(observed, dribbled_pair, start))
    return failed(counts + "; the byte-by-byte frame's pair was never echoed");
  if (!first_echo(observed, pairs.back(), start))
    return failed(counts + "; the last split frame's pair was never echoed");
  return ok(counts);
}

Outcome coalesced_frames(CaseContext& context) {
  context.run_for(milliseconds(200));
  context.streamer().set_control_output_paused(true);
  const std::int64_t start = context.now_us();
  const std::size_t closes_before = Observations::from(context.entries()).closed_us.size();
  std::vector<AckPair> lasts, all;
  for (std::size_t round = 0; round < 3 && context.streamer().vehicle_connected(); ++round) {
    std::string segment;
    for (std::size_t i = 0; i < 50; ++i) {
      const CraftedControl control{crafted_pair(31 + round, i)};
      all.push_back(control.ack);
      segment += frame_bytes(control_payload(control));
    }
    lasts.push_back(all.back());
    (void)context.streamer().write_raw_to_vehicle(segment);
    context.run_for(milliseconds(150));
  }
  context.run_for(milliseconds(200));
  const Observations observed = Observations::from(context.entries());
  std::size_t lasts_echoed = 0;
  for (const AckPair& p : lasts) lasts_echoed += first_echo(observed, p, start) != nullptr;
  const auto unknown = unknown_pairs(observed, start, all);
  const bool closed = observed.closed_us.size() > closes_before;
  const std::string counts =
      fmt::format("3 writes of 50 frames each; the last pair of {} of 3 writes echoed", lasts_echoed);
  if (closed) return failed(counts + "; connection closed: " + last_close(observed));
  if (!unknown.empty())
    return failed_over_altered_pairs(counts + "; echoed pairs never sent: " + list_pairs(unknown), unknown, observed,
                                     all);
  if (lasts_echoed < lasts.size()) return failed(counts + " (the latest pair of a write must be echoed)");
  return ok(counts);
}

Outcome oversized_inbound(CaseContext& context) {
  context.run_for(milliseconds(200));
  context.streamer().set_control_output_paused(true);
  const std::size_t closes_before = Observations::from(context.entries()).closed_us.size();
  context.note("writing a 20000-byte control frame (over the 16 KiB limit)");
  (void)context.streamer().write_raw_to_vehicle(oversized_frame(20000));
  context.run_for(milliseconds(20));
  const CraftedRun run = send_crafted(context, 10, milliseconds(10), milliseconds(300),
                                      [](std::size_t i) { return CraftedControl{crafted_pair(41, i)}; });
  if (run.closes_before > closes_before) {
    const Observations observed = Observations::from(context.entries());
    return beyond_what_the_product_sends(
        failed("the connection closed after the oversized frame: " + last_close(observed)));
  }
  return beyond_what_the_product_sends(grade_crafted(context, run, "after a skipped 20000-byte frame"));
}

Outcome responds_while_paused(CaseContext& context) {
  context.run_for(milliseconds(300));
  const std::size_t closes_before = Observations::from(context.entries()).closed_us.size();
  context.streamer().set_control_output_paused(true);
  const std::int64_t paused_at = context.now_us();
  context.note("control output paused for 2.3 s");
  context.run_for(milliseconds(2300));
  const std::int64_t resumed_at = context.now_us();
  context.streamer().set_control_output_paused(false);
  context.run_for(milliseconds(200));
  const Observations observed = Observations::from(context.entries());
  // The first close during the pause ends it: a client may keep a read timeout of its own, as
  // the product does (2 s without a byte), and close a connection whose server fell silent.
  std::int64_t end = resumed_at;
  std::string close_code;
  if (observed.closed_us.size() > closes_before) {
    end = std::min(end, observed.closed_us[closes_before]);
    close_code = observed.close_codes[closes_before];
  }
  std::int64_t last = paused_at, max_gap = 0;
  std::size_t during = 0;
  for (const Response& response : observed.all_responses) {  // any response keeps the connection alive
    if (response.time_us < paused_at || response.time_us > end) continue;
    ++during;
    max_gap = std::max(max_gap, response.time_us - last);
    last = response.time_us;
  }
  max_gap = std::max(max_gap, end - last);
  std::string counts = fmt::format("{} responses during a 2.3 s pause of control; longest silence {:.0f} ms", during,
                                   static_cast<double>(max_gap) / 1000.0);
  if (!close_code.empty()) {
    // Its timer runs from the last control frame it got (10 ms of slack for its own timer).
    const std::int64_t last_control =
        observed.latest_sent_before(paused_at) >= 0
            ? observed.sent[static_cast<std::size_t>(observed.latest_sent_before(paused_at))].time_us
            : paused_at;
    const bool own_timeout =
        close_code == "peer.closed_by_peer" && end - last_control >= product_read_timeout_us - 10'000;
    if (!own_timeout) return failed(counts + "; the connection closed: " + close_code);
    counts += fmt::format(
        "; the client closed the connection {:.0f} ms after the last control frame (a read timeout of its "
        "own, as the product's 2 s: allowed)",
        static_cast<double>(end - last_control) / 1000.0);
  }
  return grade_longest_silence(counts, max_gap);
}

// vehicle/2/1 as a standing rule: every response of every case is a decodable frame ≤ 16 KiB.
std::optional<StandingFinding> response_frame_rule(const WireLogEntry& entry) {
  if (entry.drained)
    return StandingFinding{Verdict::failed,
                           fmt::format("an oversized response (length prefix {} > 16 384)", entry.length_prefix)};
  if (!entry.ack)
    return StandingFinding{Verdict::failed, "a response that does not decode as a VehicleResponseMessage"};
  return std::nullopt;
}

}  // namespace

void add_framing_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"vehicle/2/1",
         "responses are valid frames within 16 KiB",
         "SPEC §2, seed 000 (Message framing)",
         "\"Frame = uint32 little-endian payload length, then that many bytes of UTF-8 JSON. Maximum payload: 16 384 "
         "bytes\" — "
         "\"Malformed JSON, missing required response fields, and short reads close the active TCP connection.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: ≥ 10 responses in 1 s, every one a decodable VehicleResponseMessage ≤ 16 KiB, connection never closed "
          "for bad input; "
          "and every response of every other case of the run too (a standing rule: the first offending frame is "
          "named)"},
         "vehicle_client --misbehave-oversized-frames (or --misbehave-malformed-json); broken_client.py once-oversized "
         "(with vehicle/3.3/1)"},
        valid_responses,
        response_frame_rule},
       {}});
  cases.push_back({{{"vehicle/2/3",
                     "control frames split at every byte boundary",
                     "SPEC §2",
                     "\"Frame = uint32 little-endian payload length, then that many bytes of UTF-8 JSON\" (TCP is a "
                     "byte stream: a frame may arrive in any number of pieces)",
                     Tier::must,
                     milliseconds(15'000),
                     {"OK: a frame written byte by byte and frames cut at every boundary are all read; the last pairs "
                      "echoed; connection kept"},
                     "broken_client.py naive-recv"},
                    split_frames},
                   {}});
  cases.push_back(
      {{{"vehicle/2/4",
         "many control frames coalesced in one segment",
         "SPEC §2",
         "\"Read each framed JSON control message.\" (several frames may arrive in one read)",
         Tier::must,
         milliseconds(10'000),
         {"OK: 50 frames written at once are all read; the latest pair of each write is echoed; connection kept"},
         "broken_client.py naive-recv"},
        coalesced_frames},
       {}});
  cases.push_back({{{"vehicle/2/5",
                     "survives an oversized inbound frame that the server skips",
                     "SPEC §2, seed 001",
                     "\"Inbound frame larger than that: read and discard (drain) exactly length bytes, log a warning, "
                     "keep the connection.\" — "
                     "\"messages exceeding this limit will be dropped and generate a warning message\"",
                     Tier::should,
                     milliseconds(10'000),
                     {"OK: after a 20000-byte frame the client stays connected and echoes the following frames' pairs",
                      "NON-STRICT: the client closes or stops echoing after it (the product never sends such a frame: "
                      "SPEC §2 Decision)"},
                     "broken_client.py reject-oversized (NON-STRICT)"},
                    oversized_inbound},
                   {}});
  cases.push_back(
      {{{"vehicle/2/7",
         "keeps responding while control pauses (2 s read timeout never fires)",
         "SPEC §2, seed 000 (Connect from the vehicle process)",
         "\"Keep the socket open and respond continuously.\" — \"If OCP waits about 2 seconds for response bytes while "
         "reading a frame, it closes the connection\"",
         Tier::must,
         milliseconds(12'000),
         {"OK: responses keep coming during a 2.3 s pause of control output (no silence over 1 s), connection kept",
          "NON-STRICT: its longest silence is over 1 s but under the product's 2 000 ms line (the margin is named)"},
         "broken_client.py echo-only (or vehicle_client --misbehave-silent); broken_client.py slow-keepalive "
         "(NON-STRICT)"},
        responds_while_paused},
       {}});
}

}  // namespace ocp::conformance
