// The latency-loop echo (SPEC §3.3, §5, seed 000 "Send responses"): the latest pair, unchanged,
// at once.
#include <algorithm>
#include <limits>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/pair_diagnosis.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

// The product's own line for a late loop: HighLatency past the 500 ms latency_limit (SPEC §6,
// §8). An echo further behind than that is one the product calls late (SPEC §2 Decision).
constexpr std::int64_t stale_limit_us = 500'000;
// One connection held this long (issue #35): the product keeps a connection for hours, and a
// client that stops taking the newest pair after a few seconds must not pass.
constexpr milliseconds long_connection{10'500};

Outcome latest_pair(CaseContext& context) {
  context.run_for(long_connection);
  const Observations observed = Observations::from(context.entries());
  if (observed.sent.empty()) return failed("no control frame was sent (harness)");
  const std::int64_t first_sent = observed.sent.front().time_us;
  std::size_t graded = 0, stale = 0;
  std::int64_t worst_age = 0;
  for (const Response& response : observed.responses) {
    if (response.time_us < first_sent || !response.ack) continue;
    const std::int64_t index = observed.find_sent(*response.ack);
    if (index < 0) continue;  // counted as unknown below
    ++graded;
    const std::int64_t latest = observed.latest_sent_before(response.time_us);
    const std::int64_t age = observed.sent[static_cast<std::size_t>(latest)].time_us -
                             observed.sent[static_cast<std::size_t>(index)].time_us;
    worst_age = std::max(worst_age, age);
    if (age > stale_limit_us) ++stale;
  }
  const auto unknown = unknown_pairs(observed, first_sent);
  const std::string counts = fmt::format(
      "{} control frames, {} responses echoing a sent pair, {} stale (> 500 ms behind), "
      "worst {:.1f} ms behind, {} altered",
      observed.sent.size(), graded, stale, static_cast<double>(worst_age) / 1000.0, unknown.size());
  if (!unknown.empty())
    return failed_over_altered_pairs(counts + "; altered / never-sent pairs: " + list_pairs(unknown), unknown,
                                     observed);
  if (graded < 10) return failed(counts + "; fewer than 10 responses in 10.5 s");
  if (static_cast<double>(stale) > 0.05 * static_cast<double>(graded)) {
    Outcome stale_echo = failed(counts);
    stale_echo.cause = "a stale echo: the client echoes an older pair than the latest it received; echo the latest";
    stale_echo.actual += "; cause: " + stale_echo.cause;
    return stale_echo;
  }
  return ok(counts);
}

Outcome ack_u64(CaseContext& context) {
  context.run_for(milliseconds(600));
  const std::int64_t normal_end = context.now_us();
  // Extremes the Streamer's clock will not reach in a short run: hand-made frames.
  const std::vector<AckPair> extremes{
      {std::numeric_limits<std::uint64_t>::max(), std::numeric_limits<std::uint32_t>::max()},
      {(std::uint64_t{1} << 53) + 1, 0x80000001u},
      {(std::uint64_t{1} << 63) + 12345, (1u << 31) + 7},
      {std::numeric_limits<std::uint64_t>::max() - 1, 0xFFFFFFFEu}};
  // Each extreme stays the latest pair for 120 ms: a client that echoes on its own timer (up to
  // 100 ms) echoes every one, so the case judges byte-exactness, not the echo cadence.
  const CraftedRun run = send_crafted(context, extremes.size() * 2, milliseconds(120), milliseconds(300),
                                      [&](std::size_t i) { return CraftedControl{extremes[i % extremes.size()]}; });
  const Observations observed = Observations::from(context.entries());
  const auto unknown = unknown_pairs(observed, 0);
  std::size_t normal_echoes = 0;
  for (const Response& response : observed.responses)
    normal_echoes += response.time_us < normal_end && response.ack && observed.find_sent(*response.ack) >= 0;
  std::vector<AckPair> missing;
  for (const AckPair& p : extremes) {
    if (!first_echo(observed, p, run.start_us)) missing.push_back(p);
  }
  const std::string counts =
      fmt::format("Streamer ack_time from 2^64-1-6e8 upwards: {} exact echoes; extremes {} of {} echoed exactly",
                  normal_echoes, extremes.size() - missing.size(), extremes.size());
  if (!unknown.empty()) {
    return failed_over_altered_pairs(counts + "; echoed values that were never sent: " + list_pairs(unknown), unknown,
                                     observed, extremes);
  }
  if (normal_echoes == 0) return failed(counts + "; no exact echo of the Streamer's own pairs");
  if (!missing.empty())
    return failed(counts + "; never echoed, though each was the latest pair for 120 ms: " + list_pairs(missing));
  return ok(counts);
}

// Nagle's delay on a split write (seed 000, Practical connection rules: "Use TCP no-delay if
// your client library exposes it"): a client that writes the length prefix and the payload in
// two writes without TCP_NODELAY has its payload held by the kernel until the prefix is
// acknowledged — by the Streamer's next frame (the ACK rides on it) or, with none, by the
// ~40 ms delayed ACK. Our gaps here are at most 25 ms, so its late echoes arrive right behind
// one of our later writes, whatever the gaps; a client on its own timer (or one that sleeps a
// fixed time) answers at times unrelated to our writes. True when at least 70 % of the late
// echoes (> 3 ms) arrive within 1.5 ms after a later write.
constexpr std::int64_t nagle_behind_write_us = 1'500;
bool split_write_signature(const std::vector<std::int64_t>& sent_at,
                           const std::vector<std::pair<std::size_t, std::int64_t>>& echoes) {
  std::size_t late = 0, behind = 0;
  for (const auto& [index, arrival] : echoes) {
    const std::int64_t delay = arrival - sent_at[index];
    if (delay <= 3'000) continue;
    ++late;
    bool follows_write = false;
    for (std::size_t j = index + 1; j < sent_at.size() && sent_at[j] <= arrival; ++j) {
      follows_write = follows_write || arrival - sent_at[j] <= nagle_behind_write_us;
    }
    behind += follows_write;
  }
  return late >= 10 && static_cast<double>(behind) >= 0.7 * static_cast<double>(late);
}

const char* const nagle_cause =
    "Nagle's delay on a split write: the length prefix and the payload go out in two writes without TCP_NODELAY, so "
    "the "
    "payload waits for the prefix's ACK (our next frame, or the ~40 ms delayed ACK); write each frame in one write and "
    "set "
    "TCP_NODELAY (seed 000, Practical connection rules)";

// Irregular gaps (2–25 ms, fixed sequence) separate a client that echoes at once from one
// that answers on its own timer: only the first keeps a small delay whatever the cadence.
Outcome echo_delay(CaseContext& context) {
  context.run_for(milliseconds(300));
  static constexpr int gaps_ms[] = {3, 17, 7, 23, 2, 11, 19, 5, 13, 25, 4, 9};
  std::vector<AckPair> pairs;
  std::vector<std::int64_t> sent_at;
  context.streamer().set_control_output_paused(true);
  const std::int64_t start = context.now_us();
  for (std::size_t i = 0; i < 100 && context.streamer().vehicle_connected(); ++i) {
    const CraftedControl control{crafted_pair(3, i)};
    pairs.push_back(control.ack);
    sent_at.push_back(context.now_us());
    (void)context.streamer().write_raw_to_vehicle(frame_bytes(control_payload(control)));
    context.run_for(milliseconds(gaps_ms[i % std::size(gaps_ms)]));
  }
  context.run_for(milliseconds(300));
  const Observations observed = Observations::from(context.entries(), start);
  std::vector<double> delays_ms;
  std::vector<std::pair<std::size_t, std::int64_t>> arrivals;  // (frame, echo arrival)
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (const Response* response = first_echo(observed, pairs[i], sent_at[i])) {
      delays_ms.push_back(static_cast<double>(response->time_us - sent_at[i]) / 1000.0);
      arrivals.emplace_back(i, response->time_us);
    }
  }
  if (delays_ms.empty()) return failed(fmt::format("0 of {} pairs echoed; echo delay n/a", pairs.size()));
  const double p50 = percentile(delays_ms, 50), p90 = percentile(delays_ms, 90), p99 = percentile(delays_ms, 99);
  const double max = *std::max_element(delays_ms.begin(), delays_ms.end());
  const std::string stats =
      fmt::format("{} of {} pairs echoed; echo delay p50 {:.2f} ms, p90 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms",
                  delays_ms.size(), pairs.size(), p50, p90, p99, max);
  if (delays_ms.size() < 10) return failed(stats);
  // "At once" is 3 ms of wall time for the machine's scheduling; in virtual time the client
  // answers at the instant it reads, exactly.
  if (p50 <= (context.virtual_time() ? 0.0 : 3.0)) return ok(stats);
  if (split_write_signature(sent_at, arrivals)) {  // a SHOULD of seed 000, whatever the delays
    Outcome nagle = non_strict(stats + "; the late echoes arrive right behind our next frame; cause: " + nagle_cause);
    nagle.cause = nagle_cause;
    return nagle;
  }
  if (p50 <= 20.0 && p90 <= 30.0) return non_strict(stats + " (answers on its own schedule, not at once)");
  return failed(stats);
}

Outcome no_pair_before_control(CaseContext& context) {
  context.run_for(milliseconds(400));  // control output paused from the start (setup)
  context.streamer().set_control_output_paused(false);
  const std::int64_t resumed = context.now_us();
  context.run_for(milliseconds(400));
  // This case grades exactly what the window rule leaves out of every other case: responses
  // written before the client had read a control message, including those that crossed our
  // first control frame on the wire.
  const Observations observed = Observations::from(context.entries());
  std::vector<AckPair> early;
  for (const Response& response : observed.before_control) {
    if (response.ack) early.push_back(*response.ack);
  }
  std::size_t echoes = 0;
  for (const Response& response : observed.responses)
    echoes += response.time_us >= resumed && response.ack && observed.find_sent(*response.ack) >= 0;
  if (echoes == 0)
    return failed(fmt::format("no echo of a sent pair within 400 ms after control started ({} responses before it)",
                              early.size()));
  // Before the first exact echo, a client that rounds ack_time through a double answers control
  // messages with pairs no one sent: name that cause, since the pairs are not made up.
  std::vector<AckPair> made_up;
  std::optional<std::pair<AckPair, AckPair>> rounded;  // (what it wrote, what was sent)
  const std::vector<AckPair> sent = sent_pairs(observed);
  for (const AckPair& pair : early) {
    const PairJudgement judged = judge_altered_pair(pair, sent);  // the one rule (ocp/pair_diagnosis.hpp)
    if (judged.cause == PairCause::rounded_through_double) {
      if (!rounded) rounded.emplace(pair, *judged.nearest_issued);
    } else {
      made_up.push_back(pair);
    }
  }
  const std::string rounding =
      rounded
          ? fmt::format(
                "; {} responses before the first exact echo carry sent pairs rounded through a double, e.g. {} for the "
                "sent {}, "
                "off by {} (ack_time is a u64: keep its digits, vehicle/2/2)",
                early.size() - made_up.size(), describe(rounded->first), describe(rounded->second),
                rounded->first.ack_time > rounded->second.ack_time ? rounded->first.ack_time - rounded->second.ack_time
                                                                   : rounded->second.ack_time - rounded->first.ack_time)
          : "";
  if (!made_up.empty()) {
    return non_strict(fmt::format(
        "{} responses written before the client read a control message, carrying made-up pairs such as {}{}; "
        "then {} echoes once control started",
        made_up.size(), describe(made_up.front()), rounding, echoes));
  }
  if (rounded) {
    return ok(fmt::format("no made-up pair before control{}; {} exact echoes once control started", rounding, echoes));
  }
  return ok(fmt::format("silent for 400 ms without control; {} echoes once control started", echoes));
}

}  // namespace

void add_echo_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"vehicle/3.3/1",
         "echoes the latest pair, unchanged",
         "SPEC §3.3, seed 001 (Response message)",
         "\"The response MUST include ack_time and ack_time_mac copied unmodified from the control message\" "
         "— \"The value should be the latest received by OCP.\"",
         Tier::must,
         milliseconds(20'000),
         {"OK: over one connection held 10.5 s, every echoed pair is one the Streamer sent, byte for byte, and ≤ 5 % "
          "of "
          "responses are more than 500 ms behind the latest (the latency_limit)"},
         "vehicle_client --misbehave-stop-echo (or --misbehave-corrupt-mac); broken_client.py tires"},
        latest_pair},
       {}});
  StreamerSetup u64;
  u64.ack_time_offset = std::numeric_limits<std::uint64_t>::max() - ocp_ack_time_headroom_us;
  cases.push_back(
      {{{"vehicle/2/2",
         "ack_time above 2^53 (up to 2^64-1) and ack_time_mac above 2^31 survive byte-exact",
         "SPEC §2, seed 000 (IMPORTANT box)",
         "\"Integers ack_time (u64) and ack_time_mac (u32) must survive byte-exact: never pass them through a double. "
         "Values above 2^53 are legal\" — \"must be copied byte-for-byte through your JSON number representation\"",
         Tier::must,
         milliseconds(15'000),
         {"OK: the Streamer's own pairs near 2^64-1 and hand-made pairs 2^64-1 / 2^53+1 / 2^63+12345 with MACs above "
          "2^31 come back exactly"},
         "vehicle_client --misbehave-ack-through-double"},
        ack_u64},
       u64});
  cases.push_back(
      {{{"vehicle/3.3/2",
         "echo delay distribution: answers at once",
         "seed 000 (Send responses), SPEC §5",
         "\"Send a framed JSON response that copies ack_time and ack_time_mac from the latest control message\"; "
         "\"Do not let response generation block on slow vehicle subsystems\"",
         Tier::should,
         milliseconds(15'000),
         {"OK: median echo delay ≤ 3 ms (0 ms in virtual time) over 100 control frames at irregular 2–25 ms gaps",
          "NON-STRICT: the late echoes arrive right behind the Streamer's next frame: Nagle's delay on a split write, "
          "named "
          "as the cause (seed 000, Practical connection rules: \"Use TCP no-delay\")",
          "NON-STRICT: median ≤ 20 ms and p90 ≤ 30 ms (echoes on its own timer, e.g. every 10 ms)"},
         "vehicle_client --misbehave-delay-responses-ms 50 (FAILED); broken_client.py timer-echo (NON-STRICT); "
         "broken_client.py split-write (NON-STRICT)"},
        echo_delay},
       {}});
  StreamerSetup paused;
  paused.control_paused = true;
  cases.push_back({{{"vehicle/3.3/4",
                     "no pair echoed before any control message",
                     "seed 000 (Send responses)",
                     "\"The response must include the latest ack_time and ack_time_mac values copied from an OCP "
                     "control message.\"",
                     Tier::should,
                     milliseconds(15'000),
                     {"OK: no response before the first control message, then echoes",
                      "NON-STRICT: responses with a made-up pair before any control message, then echoes"},
                     "broken_client.py early-echo (NON-STRICT); vehicle_client --misbehave-silent (FAILED)"},
                    no_pair_before_control},
                   paused});
}

}  // namespace ocp::conformance
