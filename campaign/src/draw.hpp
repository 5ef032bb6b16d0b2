#pragma once
// The campaign's seeded draws (generator.cpp, client_hazards.cpp): every number a world is
// made of comes from one of these, so a world is a pure function of its seed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "campaign/profile.hpp"

namespace ocp::campaign {

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : random_(seed) {}
  double unit() { return static_cast<double>(random_() >> 11) * 0x1.0p-53; }   // [0, 1)
  double number(double min, double max) { return min + (max - min) * unit(); }
  double number(const NumberRange& range) { return number(range.min, range.max); }
  int integer(int min, int max) {   // [min, max]
    return min + static_cast<int>(std::min<std::uint64_t>(random_() % static_cast<std::uint64_t>(max - min + 1),
                                                          static_cast<std::uint64_t>(max - min)));
  }
  // Durations are drawn in whole milliseconds: a written-back world reads "350ms", not "350217us".
  Micros duration(Micros min, Micros max) {
    const std::int64_t lo = (min.count() + 999) / 1000, hi = max.count() / 1000;
    if (hi <= lo) return Micros{lo * 1000};
    return Micros{(lo + static_cast<std::int64_t>(random_() % static_cast<std::uint64_t>(hi - lo + 1))) * 1000};
  }
  Micros duration(const DurationRange& range) { return duration(range.min, range.max); }
  bool chance(double p) { return unit() < p; }
  template <typename T>
  const T& pick(const std::vector<T>& items) { return items[static_cast<std::size_t>(integer(0, static_cast<int>(items.size()) - 1))]; }
  // Rounded to 3 significant decimals: readable in YAML, exact in round trips.
  static double tidy(double value) { return std::round(value * 1000.0) / 1000.0; }

 private:
  std::mt19937_64 random_;
};

}  // namespace ocp::campaign
