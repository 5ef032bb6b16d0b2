#include "world/seeds.hpp"

namespace ocp {
namespace {

std::uint64_t fnv1a64(std::string_view text) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char character : text) {
    hash ^= static_cast<unsigned char>(character);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// splitmix64's finaliser: spreads nearby inputs (seed 1, seed 2) over unrelated outputs.
std::uint64_t splitmix64(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ull;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ull;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebull;
  return value ^ (value >> 31);
}

}  // namespace

std::uint64_t derive_seed(std::uint64_t world_seed, std::string_view component) {
  return splitmix64(world_seed ^ fnv1a64(component));
}

MacKey derive_mac_key(std::uint64_t world_seed, std::string_view streamer_name) {
  MacKey key{};
  std::uint64_t state = derive_seed(world_seed, std::string("mac-key:").append(streamer_name));
  for (std::size_t offset = 0; offset < key.size(); offset += 8) {
    state = splitmix64(state);
    for (std::size_t byte = 0; byte < 8; ++byte) {
      key[offset + byte] = static_cast<std::uint8_t>(state >> (8 * byte));
    }
  }
  return key;
}

}  // namespace ocp
