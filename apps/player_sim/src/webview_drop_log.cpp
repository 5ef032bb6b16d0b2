// Log-once-then-summarise for dropped web view messages.
#include <fmt/format.h>

#include <utility>

#include "player_app/webview/drop_log.hpp"

namespace ocp::webview {

std::string_view drop_kind_name(DropKind kind) {
  switch (kind) {
    case DropKind::malformed: return "malformed";
    case DropKind::unknown_name: return "unknown name";
    case DropKind::oversized: return "oversized";
    case DropKind::binary: return "binary";
    case DropKind::flood: return "over the rate limit";
  }
  return "?";
}

DropLog::DropLog(Logger logger, std::string peer, Micros summary_period)
    : logger_(std::move(logger)), peer_(std::move(peer)), summary_period_(summary_period) {}

bool DropLog::dropped(DropKind kind, SimTime now, std::string_view detail) {
  const auto index = static_cast<std::size_t>(kind);
  if (totals_[index]++ == 0) {
    logger_.warn("web view client {}: {} message dropped: {} (further ones are counted and summarised)", peer_,
                 drop_kind_name(kind), detail);
    if (last_summary_ == SimTime{0}) last_summary_ = now;
    return true;
  }
  ++unreported_[index];
  if (now - last_summary_ >= summary_period_) summarise(now);
  return false;
}

void DropLog::flush() { summarise(last_summary_); }

void DropLog::summarise(SimTime now) {
  std::string counts;
  for (std::size_t i = 0; i < drop_kind_count; ++i) {
    if (unreported_[i] == 0) continue;
    counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", unreported_[i], drop_kind_name(static_cast<DropKind>(i)));
    unreported_[i] = 0;
  }
  last_summary_ = now;
  if (counts.empty()) return;
  logger_.warn("web view client {}: more messages dropped since the last report: {}", peer_, counts);
}

}  // namespace ocp::webview
