// Verdicts on notable events (verdicts_internal.hpp): a source lock or conflict, a connection
// closed or refused, that must happen in a window or never.
#include "verdicts_internal.hpp"

namespace ocp::scenario {
namespace {

bool notable_matches(const EventExpectation& e, const NotableEvent& n) {
  if (n.kind != e.kind) return false;
  if (e.source && n.source != *e.source) return false;
  if (e.locked && n.locked != *e.locked) return false;
  const bool connection = e.kind == NotableKind::connection_closed || e.kind == NotableKind::connection_refused;
  if (!connection) return true;
  if (n.wire != e.wire || (e.vehicle && n.component != *e.vehicle)) return false;
  return n.reason.find(e.reason) != std::string::npos;
}

std::string describe_notable(const NotableEvent& n) {
  std::string text(notable_kind_name(n.kind));
  switch (n.kind) {
    case NotableKind::source_locked: text.append(" ").append(client_source_name(n.source)); break;
    case NotableKind::source_conflict:
      text.append(" locked ").append(client_source_name(n.locked)).append(" offending ").append(client_source_name(n.source));
      break;
    default: text.append(" on ").append(n.component).append(" '").append(n.reason).append("'"); break;
  }
  return text.append(" at ").append(format_seconds(n.time));
}

}  // namespace

void judge_event(const JudgeContext& context, const EventExpectation& e, Verdict& v) {
  v.kind = "event";
  const SimTime end = e.until.value_or(context.scenario.duration);
  const SimTime start = e.from + e.min;   // within [min, max]: not before from + min
  v.expected = std::string(e.never ? "no " : "") + std::string(notable_kind_name(e.kind)) + " in [" +
               format_seconds(start) + ", " + format_seconds(end) + "]";
  std::size_t seen = 0;
  const NotableEvent* first = nullptr;
  const NotableEvent* other = nullptr;   // the same kind of event, not matching: the likely near miss
  for (const NotableEvent& n : context.observations.notable_events) {
    if (n.time >= e.from && n.time < start && notable_matches(e, n) && other == nullptr) other = &n;   // too early
    if (n.time < start || n.time > end) continue;
    if (!notable_matches(e, n)) {
      if (other == nullptr && n.kind == e.kind) other = &n;
      continue;
    }
    if (first == nullptr) first = &n;
    ++seen;
  }
  if (e.never) {
    v.passed = seen == 0;
    v.actual = seen == 0 ? "none" : std::to_string(seen) + " time(s), first: " + describe_notable(*first);
    if (v.passed && !context.ran_past(end - Micros{1})) context.cut_short(v);
    return;
  }
  v.passed = first != nullptr;
  v.actual = first != nullptr ? describe_notable(*first)
                              : "none in the window" + (other != nullptr ? "; nearest: " + describe_notable(*other) : "");
  if (!v.passed && !context.ran_past(end)) context.cut_short(v);
}

}  // namespace ocp::scenario
