#pragma once
// Client data source locking (SPEC §4.3, seed 003): the first source to send client data is
// locked in; data from a different source afterwards is a configuration error that stops all
// client data from every source until restart.
#include <optional>

#include "ocp/log.hpp"
#include "player/player_core.hpp"

namespace ocp {

class SourceLock {
 public:
  // True when data from `source` may be applied. Locks on first use; on a conflict logs an
  // error naming both sources and stops everything (then and afterwards returns false).
  [[nodiscard]] bool admit(ClientSource source, const Logger& logger);

  std::optional<ClientSource> locked() const { return locked_; }
  bool stopped() const { return stopped_; }
  bool conflict_just_happened() const { return conflict_just_happened_; }

 private:
  bool decide(ClientSource source, const Logger& logger);   // admit() without its invariants
  std::optional<ClientSource> locked_;
  bool stopped_ = false;
  bool conflict_just_happened_ = false;
};

}  // namespace ocp
