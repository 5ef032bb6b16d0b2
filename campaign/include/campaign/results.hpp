#pragma once
// A campaign's results as files: summary.json (the record merge reads back), JUnit, the HTML
// index, and the terminal table. Nothing here depends on time or on how the worlds were split
// into shards, so merge(shards) writes byte for byte what one run of the same seeds writes.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "campaign/campaign.hpp"

namespace ocp::campaign {

struct ViolationRecord {
  std::string check;
  std::int64_t at_us = 0;
  std::string vehicle;
  std::string detail;
};

struct WorldRecord {
  std::uint64_t index = 0;
  std::uint64_t seed = 0;
  std::int64_t duration_us = 0;
  int vehicles = 0;
  int timeline_events = 0;
  bool determinism_checked = false;
  bool liveness_checked = false;
  std::uint64_t violation_count = 0;
  std::string error;
  std::vector<ViolationRecord> violations;   // the first few
  // A failing world's folder: the files written there (failure_dir()/…) and the command that
  // replays it. Recorded, not looked up, so a merge writes what one run writes.
  std::vector<std::string> files;
  std::string replay;
  std::vector<std::string> hazards;   // a client world's (client_world.hpp, hazards_in)
  bool failed() const { return violation_count > 0 || !error.empty(); }
  std::string failure_dir() const { return "failures/world-" + std::to_string(index); }
};

struct Summary {
  std::uint64_t seed = 0;
  std::string profile;
  std::uint64_t profile_digest = 0;
  std::uint64_t worlds = 0;        // the whole campaign's
  Shard shard;
  bool interrupted = false;
  bool client_worlds = false;         // --client
  bool client_real_time = false;      // --client --time real: the oracle's timing checks off
  std::vector<WorldRecord> records;   // by index
};

class MergeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Summary summarise(const CampaignOptions& options, const CampaignRun& run);
std::string summary_json(const Summary& summary);
Summary read_summary_json(const std::string& text, const std::string& path);   // throws MergeError
// Joins shards of one campaign; refuses shards of another (seed, profile, size) or a shard twice.
Summary merge_summaries(const std::vector<Summary>& shards);
std::string junit_xml(const Summary& summary);
std::string html_index(const Summary& summary);
// The table of checks (✓/✗ and the worlds failing each; "—" with the reason for a check that
// was not judged), then each failing world's first violation and replay command.
std::string summary_table(const Summary& summary);

}  // namespace ocp::campaign
