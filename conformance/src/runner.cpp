#include "conformance/runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>

#include "conformance/case_context.hpp"
#include "conformance/standing_rules.hpp"
#include "conformance/streamer_host.hpp"
#include "sim_app/client_process.hpp"

namespace ocp::conformance {
using sim_app::ClientProcess;
using sim_app::describe_exit_status;
using sim_app::last_lines_of;
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Every case grades a connected client, so its body starts only once the client is connected
// (10 s at most). A client that never connects fails a MUST or SHOULD case; an INFO case only
// observes, so for it there is nothing measured.
Outcome play(const VehicleCase& test_case, CaseContext& context) {
  if (context.wait_connected()) return test_case.body.run(context);
  if (test_case.body.info.tier == Tier::info)
    return {Verdict::informational, "the client did not connect within 10 s: nothing measured", {}};
  return {Verdict::failed, "the client did not connect within 10 s", {}};
}

struct Shared {
  Shared(const std::vector<VehicleCase>& all, const RunOptions& run_options) : cases(all), options(run_options) {}
  const std::vector<VehicleCase>& cases;
  const RunOptions& options;
  std::atomic<std::size_t> next{0};
  std::vector<CaseResult> results;
  std::size_t reported = 0;  // results[0, reported) went to on_result, in case order
  std::size_t finished = 0;
  // Per case that carries a standing rule: the first offending frame found in any case so far.
  std::vector<std::optional<StandingHit>> standing_hits;
  std::mutex mutex;
  std::string harness_error;
  bool interrupted = false;

  void fail(std::string error) {
    std::lock_guard lock(mutex);
    if (harness_error.empty()) harness_error = std::move(error);
  }
  bool failed() {
    std::lock_guard lock(mutex);
    return !harness_error.empty() || interrupted;
  }
  void interrupt() {
    std::lock_guard lock(mutex);
    interrupted = true;
  }
  // Stores one result and reports every result whose predecessors are all done: with jobs > 1
  // the lines still come out in case order.
  // A case with a standing rule is reported only when every case is done (they run last: see
  // run_cases), with the first offending frame of the whole run folded in.
  void finish_case(std::size_t index, CaseResult result) {
    std::lock_guard lock(mutex);
    results[index] = std::move(result);
    ++finished;
    report_in_order(false);
  }
  void report_in_order(bool run_over) {
    while (reported < results.size() && !results[reported].info.id.empty()) {
      if (cases[reported].body.standing) {
        if (!run_over && finished < results.size()) return;
        if (standing_hits[reported]) apply_standing_hit(results[reported], *standing_hits[reported]);
      }
      if (options.on_result) options.on_result(results[reported]);
      ++reported;
    }
  }
  // Every standing rule of the run, over one finished case's wire log.
  void scan_standing(std::size_t index, const std::vector<WireLogEntry>& entries) {
    for (std::size_t rule = 0; rule < cases.size(); ++rule) {
      auto hit = first_standing_violation(cases[rule].body.standing, entries, index, cases[index].body.info.id);
      if (!hit) continue;
      std::lock_guard lock(mutex);
      keep_first_hit(standing_hits[rule], std::move(*hit));
    }
  }
};

std::string log_path(const RunOptions& options, const std::string& name) {
  if (options.client_log_dir.empty()) return "";
  std::string file = name;
  for (char& c : file) {
    if (c == '/') c = '_';
  }
  return options.client_log_dir + "/" + file + ".log";
}

// Waits until the launched client connected to the current Streamer (or Player) at least once;
// a client connected and already closed again counts, it is the case's to grade.
void wait_for_first_connection(StreamerHost& host, ClientProcess& client, const std::string& client_log,
                               const RunOptions& options) {
  const auto limit = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::duration<double, std::milli>(
      static_cast<double>(options.connect_timeout.count()) * options.timeout_scale));
  const auto connected = [&] { return host.client_connections_accepted() > 0; };
  (void)host.run_until([&] { return connected() || !client.running(); }, limit);
  if (connected()) return;
  const std::string what = client.running() ? fmt::format(
                                                  "did not connect to 127.0.0.1:{} within {:.1f} s of its launch (a "
                                                  "slow starter: raise --connect-timeout-s)",
                                                  host.port(), std::chrono::duration<double>(limit).count())
                                            : fmt::format("{} before it connected to 127.0.0.1:{}",
                                                          describe_exit_status(*client.exit_status()), host.port());
  const std::string output = last_lines_of(client_log, 10);
  const std::string where = options.client_logs_kept ? " (" + client_log + ")" : "";
  const std::string keep = options.client_logs_kept ? "" : "\n  (rerun with --out DIR to keep its whole output)";
  const std::string said = client_log.empty() ? "rerun with --out DIR to keep its output"
                           : output.empty()   ? "it wrote nothing"
                                              : "the last lines it wrote" + where + ":" + output + keep;
  throw std::runtime_error(fmt::format("the client {}; {}", what, said));
}

// Launches the client for `host`: in virtual time under the shim, announced to the controller
// (which must not outlive its process record: it looks through a weak pointer).
std::shared_ptr<ClientProcess> launch_client(StreamerHost& host, const RunOptions& options, const std::string& log) {
  vtime::Controller* controller = host.controller();
  auto launched = ClientProcess::launch(options.command, host.port(), log,
                                        controller != nullptr ? controller->environment() : std::vector<std::string>{});
  if (!launched) throw std::runtime_error(launched.error().message());
  std::shared_ptr<ClientProcess> client = std::move(*launched);
  if (controller != nullptr) {
    controller->expect_process(client->pid(), "the client", [process = std::weak_ptr<ClientProcess>(client)] {
      const auto alive = process.lock();
      return alive && alive->running();
    });
  }
  return client;
}

CaseResult run_one(Shared& shared, StreamerHost& host, std::size_t index, std::shared_ptr<ClientProcess>& client,
                   std::string& client_log, unsigned worker) {
  const VehicleCase& test_case = shared.cases[index];
  const RunOptions& options = shared.options;
  CaseResult result;
  result.info = test_case.body.info;
  const auto start = Clock::now();
  WireLog log;
  if (auto status = host.start_streamer(test_case.setup); !status) {
    throw std::runtime_error("cannot start the Streamer: " + status.error().message());
  }
  log.attach(host.client_events(), test_case.setup.operator_side ? Wire::operator_ : Wire::vehicle);
  const bool launching = !options.command.empty();
  bool client_was_launched = false;
  if (launching && (options.restart_per_case || !client || !client->running())) {
    client_was_launched = true;
    // A shared client that died is relaunched: the next cases still get graded.
    if (client && !options.restart_per_case) log.note(host.now_us(), "the client had exited: relaunched");
    client.reset();
    const std::string path =
        log_path(options, options.restart_per_case ? test_case.body.info.id : fmt::format("worker-{}", worker));
    client = launch_client(host, options, path);
    client_log = path;
  }
  result.client_log_path = launching && options.client_logs_kept ? client_log : std::string();
  // A client just launched (a new process, or one relaunched after it died) is given its own
  // bounded time to start and connect before the case's clock starts: starting is no part of
  // what the case grades. A client that exits or never connects cannot be graded at all: the
  // run stops with a harness error at once, instead of timing out case after case.
  if (client_was_launched) wait_for_first_connection(host, *client, client_log, options);
  const bool client_was_running = client && client->running();
  const auto timeout = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::duration<double, std::milli>(
      static_cast<double>(test_case.body.info.timeout.count()) * options.timeout_scale));
  CaseContext context(host, log, host.now_us() + timeout.count(), options.timeout_scale);
  context.set_interlock(options.interlock);
  try {
    const Outcome outcome = play(test_case, context);
    result.verdict = outcome.verdict;
    result.actual = outcome.actual;
    result.cause = outcome.cause;
  } catch (const CaseTimeout&) {
    // An INFO case only observes: running out of time is its observation, never a failure.
    result.verdict = test_case.body.info.tier == Tier::info ? Verdict::informational : Verdict::failed;
    result.actual = fmt::format("the case did not finish within its {:.1f} s timeout",
                                std::chrono::duration<double>(timeout).count());
  }
  if (client_was_running && !client->running()) {
    result.actual += fmt::format(" (the client {} during the case)", describe_exit_status(*client->exit_status()));
  }
  host.stop_streamer();
  log.detach();
  shared.scan_standing(index, log.entries());
  if (options.restart_per_case) client.reset();
  result.duration_ms = ms_since(start);
  if (result.verdict != Verdict::ok) result.wire_log = log.take();
  return result;
}

// The worker's host: on the wall clock, or on its own virtual clock with a controller.
std::unique_ptr<StreamerHost> make_host(const RunOptions& options) {
  if (options.virtual_time) return std::make_unique<StreamerHost>(options.controller);
  return std::make_unique<StreamerHost>();
}

void worker_main(Shared& shared, unsigned worker) {
  const RunOptions& options = shared.options;
  std::unique_ptr<StreamerHost> made;
  try {
    made = make_host(options);
  } catch (const std::exception& error) {
    shared.fail(std::string("virtual time: ") + error.what());
    return;
  }
  StreamerHost& host = *made;
  if (options.stop_requested) host.stop_when(options.stop_requested);
  const std::uint16_t port = options.command.empty() ? options.port : (options.jobs > 1 ? 0 : options.port);
  if (auto status = host.listen(port); !status) {
    shared.fail("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + status.error().message());
    return;
  }
  std::shared_ptr<ClientProcess> client;
  std::string client_log;
  while (!shared.failed()) {
    const std::size_t index = shared.next.fetch_add(1);
    if (index >= shared.cases.size()) break;
    try {
      shared.finish_case(index, run_one(shared, host, index, client, client_log, worker));
    } catch (const RunInterrupted&) {
      shared.interrupt();
    } catch (const std::exception& error) {
      shared.fail(fmt::format("{}: harness error: {}", shared.cases[index].body.info.id, error.what()));
    }
  }
  client.reset();  // killed on every path, also after a harness error
}

}  // namespace

RunSummary run_cases(const std::vector<VehicleCase>& cases, const RunOptions& options) {
  const auto start = Clock::now();
  // Concurrency needs one client (and port) per worker: only with a launched client.
  const unsigned jobs = options.command.empty()
                            ? 1u
                            : std::max(1u, std::min<unsigned>(options.jobs, static_cast<unsigned>(cases.size())));
  RunOptions effective = options;
  effective.jobs = jobs;
  // Cases with a standing rule run last, so they can be reported as soon as the rest is done.
  std::vector<VehicleCase> ordered = cases;
  std::stable_partition(ordered.begin(), ordered.end(), [](const VehicleCase& c) { return !c.body.standing; });
  Shared run(ordered, effective);
  run.results.resize(ordered.size());
  run.standing_hits.resize(ordered.size());
  std::vector<std::thread> workers;
  for (unsigned w = 1; w < jobs; ++w) workers.emplace_back([&run, w] { worker_main(run, w); });
  worker_main(run, 0);
  for (std::thread& t : workers) t.join();
  run.report_in_order(true);  // an interrupted or failed run still reports what it finished
  RunSummary summary;
  summary.duration_ms = ms_since(start);
  summary.harness_error = run.harness_error;
  summary.interrupted = run.interrupted;
  summary.cases_selected = cases.size();
  for (std::size_t i = 0; i < ordered.size(); ++i) {
    if (!run.results[i].info.id.empty()) summary.results.push_back(std::move(run.results[i]));
  }
  return summary;
}

}  // namespace ocp::conformance
