// LinkSeriesBuilder (link_series.hpp): the report's link throughput and queueing delay.
#include "link_series.hpp"

#include <algorithm>

namespace ocp::scenario {
namespace {

constexpr double link_bucket_seconds = static_cast<double>(LinkSeriesBuilder::bucket.count()) / 1e6;

SimTime bucket_start(SimTime now) {
  return SimTime{now.count() / LinkSeriesBuilder::bucket.count() * LinkSeriesBuilder::bucket.count()};
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

// Empty buckets between the last one and `start` read as zero throughput, so the line drops
// to the floor across a gap (a tunnel) instead of sloping over it.
void LinkSeriesBuilder::add_delivery(SimTime now, std::size_t bytes, Micros queueing, LinkSeries& out) {
  const SimTime start = bucket_start(now);
  const double queueing_ms = static_cast<double>(queueing.count()) / 1000.0;
  if (bucket_start_ != start) {
    if (bucket_start_) {
      const SimTime after_last = *bucket_start_ + LinkSeriesBuilder::bucket;
      if (after_last < start) out.throughput_mbps.add(after_last, 0.0);
      if (after_last < start - LinkSeriesBuilder::bucket) out.throughput_mbps.add(start - LinkSeriesBuilder::bucket, 0.0);
    }
    bucket_start_ = start;
    bucket_mbps_ = 0;
    bucket_queueing_ms_ = queueing_ms;
    out.throughput_mbps.add(start, 0.0);
    out.queueing_delay_ms.add(start, queueing_ms);
  }
  bucket_mbps_ += static_cast<double>(bytes) * 8.0 / link_bucket_seconds / 1e6;
  bucket_queueing_ms_ = std::max(bucket_queueing_ms_, queueing_ms);
  out.throughput_mbps.raise_last(bucket_mbps_);
  out.queueing_delay_ms.raise_last(bucket_queueing_ms_);
}

}  // namespace ocp::scenario
