#include "world/virtual_world.hpp"

#include <utility>

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

WorldConfig with_deterministic_keys(WorldConfig config) {
  config.deterministic_keys = true;
  return config;
}

LogSink combine(LogSink first, LogSink second) {
  if (!second) return first;
  return [first = std::move(first), second = std::move(second)](const LogRecord& record) {
    first(record);
    second(record);
  };
}

}  // namespace

VirtualWorld::VirtualWorld(WorldConfig config, TraceOptions trace_options, LogSink extra_sink)
    : world_(executor_, with_deterministic_keys(std::move(config)),
             combine(log_.sink(), std::move(extra_sink))),
      trace_(world_.events(), trace_options) {}

Status VirtualWorld::start() { return world_.start(); }

bool VirtualWorld::run_until_condition(const std::function<bool()>& condition, Micros limit) {
  const SimTime end = executor_.now() + limit;
  if (condition()) return true;
  while (executor_.next_deadline() <= end) {
    executor_.step();
    if (condition()) return true;
  }
  executor_.run_until(end);
  OCP_INVARIANT(executor_.now() >= end, "a run that never met its condition ran to its limit");
  return condition();
}

}  // namespace ocp
