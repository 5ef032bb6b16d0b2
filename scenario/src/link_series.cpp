// LinkSeriesBuilder (link_series.hpp): the report's link throughput and queueing delay.
#include "link_series.hpp"

#include <algorithm>

namespace ocp::scenario {
namespace {

constexpr double link_bucket_seconds = static_cast<double>(LinkSeriesBuilder::bucket.count()) / 1e6;

SimTime bucket_start(SimTime now) {
  return SimTime{now.count() / LinkSeriesBuilder::bucket.count() * LinkSeriesBuilder::bucket.count()};
}

// Empty buckets between the last sample and `start` read as zero throughput, so the line
// drops to the floor across a gap (a tunnel) instead of sloping over it.
void zero_fill(std::vector<Sample>& series, SimTime start) {
  if (series.empty()) return;
  const SimTime after_last = series.back().time + LinkSeriesBuilder::bucket;
  if (after_last < start) series.push_back({after_last, 0.0});
  if (after_last < start - LinkSeriesBuilder::bucket) series.push_back({start - LinkSeriesBuilder::bucket, 0.0});
}

}  // namespace

void LinkSeriesBuilder::on_link_event(const LinkEvent& event, SimTime now, LinkSeries& out) {
  switch (event.outcome) {
    case LinkOutcome::sent:
      sent_.emplace(event.message_id, now);
      if (sent_.size() > max_unsettled) sent_.erase(sent_.begin());
      return;
    case LinkOutcome::dropped:
      sent_.erase(event.message_id);
      return;
    case LinkOutcome::duplicated: return;   // the first copy delivered is the one measured
    case LinkOutcome::delivered: {
      const auto found = sent_.find(event.message_id);
      if (found == sent_.end()) return;   // a duplicate, or sent before the run was observed
      const Micros queueing = std::max(Micros{0}, now - found->second - propagation_);
      sent_.erase(found);
      add_delivery(now, event.size_bytes, queueing, out);
      return;
    }
  }
}

void LinkSeriesBuilder::add_delivery(SimTime now, std::size_t bytes, Micros queueing, LinkSeries& out) {
  const SimTime start = bucket_start(now);
  if (out.throughput_mbps.empty() || out.throughput_mbps.back().time != start) {
    zero_fill(out.throughput_mbps, start);
    out.throughput_mbps.push_back({start, 0.0});
  }
  out.throughput_mbps.back().value += static_cast<double>(bytes) * 8.0 / link_bucket_seconds / 1e6;
  const double queueing_ms = static_cast<double>(queueing.count()) / 1000.0;
  if (out.queueing_delay_ms.empty() || out.queueing_delay_ms.back().time != start) {
    out.queueing_delay_ms.push_back({start, queueing_ms});
  } else {
    out.queueing_delay_ms.back().value = std::max(out.queueing_delay_ms.back().value, queueing_ms);
  }
}

}  // namespace ocp::scenario
