#pragma once
// Messages of one link direction in flight, each with its copies and what a check remembered
// when it was sent. A message is in flight once for its send and once more for each copy the
// link announced (LinkOutcome::duplicated); each delivery or drop takes one. Counted, never
// timed: real time delivers two copies microseconds apart (issue #34). The oracle's
// conservation, its feedback lists and the locked-source rule all keep one.
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <variant>

namespace ocp::campaign {

template <class Value = std::monostate>
class CopiesInFlight {
 public:
  // A message sent: one copy. False (nothing kept) when `limit` messages are kept already.
  bool send(std::uint64_t message, Value value = {}, std::size_t limit = std::numeric_limits<std::size_t>::max()) {
    if (messages_.size() >= limit) return false;
    messages_[message] = Entry{std::move(value), 1};
    ++copies_;
    return true;
  }
  bool contains(std::uint64_t message) const { return messages_.contains(message); }
  // One more copy of a message in flight; false when it is not.
  bool duplicate(std::uint64_t message) {
    const auto found = messages_.find(message);
    if (found == messages_.end()) return false;
    ++found->second.copies;
    ++copies_;
    return true;
  }
  // One copy delivered or dropped: what was kept at its send, or nullopt when none is in flight.
  std::optional<Value> take(std::uint64_t message) {
    const auto found = messages_.find(message);
    if (found == messages_.end()) return std::nullopt;
    std::optional<Value> value = found->second.value;
    --copies_;
    if (--found->second.copies == 0) messages_.erase(found);
    return value;
  }
  std::uint64_t copies() const { return copies_; }   // every copy of every message

 private:
  struct Entry {
    Value value;
    std::uint32_t copies = 0;
  };
  std::unordered_map<std::uint64_t, Entry> messages_;
  std::uint64_t copies_ = 0;
};

}  // namespace ocp::campaign
