#include "ocp/raw_pieces.hpp"

namespace ocp {

Status write_raw_in_pieces(Executor& executor, const std::shared_ptr<FramedConnection>& connection,
                           std::string bytes, const std::vector<std::size_t>& cuts, Micros gap) {
  std::vector<std::size_t> bounds{0};
  for (const std::size_t cut : cuts) {
    if (cut > bounds.back() && cut < bytes.size()) bounds.push_back(cut);
  }
  bounds.push_back(bytes.size());
  auto shared = std::make_shared<const std::string>(std::move(bytes));
  Status first = connection->write_raw(std::string_view(*shared).substr(0, bounds[1]));
  if (!first) return first;
  std::weak_ptr<FramedConnection> target = connection;
  for (std::size_t i = 1; i + 1 < bounds.size(); ++i) {
    (void)executor.call_after(gap * static_cast<std::int64_t>(i), [target, shared, from = bounds[i], to = bounds[i + 1]] {
      const auto same = target.lock();
      // A closed connection is never reopened: its successor is another object.
      if (!same || !same->is_open()) return;
      (void)same->write_raw(std::string_view(*shared).substr(from, to - from));
    });
  }
  return Ok{};
}

}  // namespace ocp
