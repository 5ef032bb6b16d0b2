#pragma once
// One link direction's report series (LinkSeries, observer.hpp), built from its LinkEvents as
// they come: delivered throughput and queueing delay per 100 ms bucket. The queueing delay of
// a delivered message is its one-way delay (delivered − sent) less the direction's set
// propagation delay (Impairments::delay): the time it waited in a queue, or in jitter.
#include <cstdint>
#include <map>
#include <optional>

#include "ocp/events.hpp"
#include "scenario/observer.hpp"

namespace ocp::scenario {

class LinkSeriesBuilder {
 public:
  static constexpr Micros bucket{100'000};
  static constexpr std::size_t max_unsettled = 1 << 16;   // messages never delivered nor dropped

  void set_propagation_delay(Micros delay) { propagation_ = delay; }
  void on_link_event(const LinkEvent& event, SimTime now, LinkSeries& out);

 private:
  void add_delivery(SimTime now, std::size_t bytes, Micros queueing, LinkSeries& out);
  std::map<std::uint64_t, SimTime> sent_;   // message id → when sent, until it settles
  Micros propagation_{0};
  // The bucket filling now (the series' points may stand for several buckets each).
  std::optional<SimTime> bucket_start_;
  double bucket_mbps_ = 0, bucket_queueing_ms_ = 0;
};

}  // namespace ocp::scenario
