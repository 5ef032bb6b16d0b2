#pragma once
// "did you mean 'latency_limit'?" for every name a scenario file can misspell: keys, faults,
// actions, metrics, vehicles, events, … One rule everywhere, so that every message reads alike.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ocp::scenario {

// Edit distance (insertions, deletions, substitutions and swaps of two neighbours, each 1),
// ignoring case: "HighLatncy" and "highlatency" are both one keystroke from "HighLatency".
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word`, if it is close enough to be a typo: at most a third of the
// word's length apart (at least 1, at most 3). Ties go to the first candidate.
std::optional<std::string> closest_name(std::string_view word, const std::vector<std::string>& candidates);

// "unknown fault 'HighLatncy': did you mean 'HighLatency'?" — or, with nothing close,
// "unknown fault 'TooHot' (known: VehicleNoResponse, …)". `what` names the kind of thing,
// `where` (optional) the place: "unknown key 'latency_limt' in vehicle: did you mean …".
std::string unknown_name(std::string_view what, std::string_view word, const std::vector<std::string>& candidates,
                         std::string_view where = {});

}  // namespace ocp::scenario
