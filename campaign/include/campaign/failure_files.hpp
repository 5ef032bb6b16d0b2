#pragma once
// The files of one failing world (failures/world-<i>/ under the results folder): world.yaml
// (the generated world as it ran), shrunk.yaml (the shrunk regression scenario with its
// repro command) and report.html (the scenario runner's report of the shrunk world).
#include <optional>
#include <string>
#include <vector>

#include "campaign/client_world.hpp"
#include "campaign/profile.hpp"
#include "ocp/time.hpp"

namespace ocp::campaign {

// Each try of a client world runs the client: fewer tries than for in-process worlds.
inline constexpr int client_shrink_runs = 40;

struct FailureFilesOptions {
  std::string out_dir;
  std::uint64_t campaign_seed = 0;
  std::uint64_t worlds = 0;
  std::string profile_argument;   // as the user gave it, for the repro command
  bool shrink = true;
  int shrink_runs = 300;
  // A --client campaign: world.yaml is the client world, the repro command names the client.
  // In real time nothing is shrunk (every try would be a real-time run); in virtual time
  // (`run` set, --time virtual) the world is shrunk with the client, at most
  // client_shrink_runs tries, and shrunk.yaml carries the repro command.
  struct Client {
    std::string command;
    std::optional<double> max_world_seconds;   // as the user gave it
    std::optional<Micros> max_world;
    std::optional<ClientRun> run;              // set: virtual time, shrink with it
  };
  std::optional<Client> client;
};

struct FailureFiles {
  std::vector<std::string> files;   // the names written into the folder, in the order written
  std::string replay;               // the one-line command that runs the world again
  int shrunk_events = -1;           // the shrunk world's timeline size (−1: not shrunk)
};

// Writes the folder for world `index`.
FailureFiles write_failure_files(const Profile& profile, std::uint64_t index, const FailureFilesOptions& options);

}  // namespace ocp::campaign
