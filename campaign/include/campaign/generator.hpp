#pragma once
// The world generator: campaign seed + world index → one scenario model (scenario/model.hpp),
// so a generated world runs through the ordinary scenario runner in virtual time and can be
// written back as ordinary scenario YAML (scenario/write.hpp). A pure function of its inputs:
// the same campaign seed gives the same worlds on every machine (the draws are our own code
// on std::mt19937_64, whose output the standard fixes).
#include <cstdint>

#include "campaign/profile.hpp"
#include "scenario/model.hpp"

namespace ocp::campaign {

// World i's own seed: derive_seed(campaign_seed, "world:<i>") (world/src/seeds.cpp), so a
// world never depends on how many draws another world made.
std::uint64_t world_seed(std::uint64_t campaign_seed, std::uint64_t index);

// World `index` of the campaign. Its name is "world-<index>", its seed world_seed(…).
scenario::Scenario generate_world(const Profile& profile, std::uint64_t campaign_seed, std::uint64_t index);

}  // namespace ocp::campaign
