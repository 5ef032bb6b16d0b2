#pragma once
// Per-component random seeds (ARCHITECTURE.md property 3). Every component draws from its own
// generator, seeded from the world seed and a stable component name, so one component's
// draws never depend on how many draws another made, or on which other components exist.
#include <cstdint>
#include <string>
#include <string_view>

#include "ocp/mac.hpp"

namespace ocp {

// splitmix64(world_seed ^ fnv1a64(component)): stable across platforms and runs.
std::uint64_t derive_seed(std::uint64_t world_seed, std::string_view component);

// A MAC key derived from the world seed for one Streamer. Test mode only: a real Streamer's
// key comes from the CSPRNG and never leaves it (SPEC §5.1).
MacKey derive_mac_key(std::uint64_t world_seed, std::string_view streamer_name);

}  // namespace ocp
