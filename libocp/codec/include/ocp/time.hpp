#pragma once
// Time as the whole simulator sees it: microseconds since a world (or process) started.
// Nothing in a protocol core reads a clock; `now` is always passed in as a SimTime.
#include <chrono>
#include <cstdint>

namespace ocp {

using Micros = std::chrono::microseconds;
using Millis = std::chrono::milliseconds;

// A point on a world's timeline, measured from the world's start. Same type as a duration
// on purpose: arithmetic stays trivial and printing it is `count()` microseconds.
using SimTime = std::chrono::microseconds;

inline constexpr std::int64_t to_whole_ms(Micros value) { return value.count() / 1000; }

}  // namespace ocp
