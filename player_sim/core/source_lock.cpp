// Client data source locking (SPEC §4.3).
#include "source_lock.hpp"

#include "ocp/invariant.hpp"

namespace ocp {

bool is_keep_alive(const ClientOcpShared& data) {
  if (data.active_vehicle) return false;
  for (const auto& [name, entry] : data.client_user_data) {
    if (entry != ClientVehicleEntry{}) return false;
  }
  return true;
}

bool is_keep_alive(ClientSource source, const ClientOcpShared& data) {
  if (source != ClientSource::webview) return is_keep_alive(data);
  return !data.active_vehicle && data.client_user_data.empty();
}

bool SourceLock::admit(ClientSource source, const Logger& logger) {
  const std::optional<ClientSource> locked_before = locked_;
  const bool stopped_before = stopped_;
  const bool admitted = decide(source, logger);
  // The lock is monotone: unlocked → locked to one source → stopped, never back.
  OCP_INVARIANT(!locked_before || locked_ == locked_before, "a locked source never changes until restart");
  OCP_INVARIANT(!stopped_before || stopped_, "a stopped source lock stays stopped until restart");
  OCP_INVARIANT(!admitted || (locked_ == source && !stopped_), "only the locked source is admitted, and only while not stopped");
  OCP_INVARIANT(!stopped_ || locked_.has_value(), "only a locked source can conflict");
  return admitted;
}

bool SourceLock::decide(ClientSource source, const Logger& logger) {
  conflict_just_happened_ = false;
  if (stopped_) return false;
  if (!locked_) {
    locked_ = source;
    logger.info("client data source locked: {}", client_source_name(source));
    return true;
  }
  if (*locked_ == source) return true;
  stopped_ = true;
  conflict_just_happened_ = true;
  logger.error(
      "client data source conflict: locked source '{}', conflicting source '{}'; all client "
      "data (user data and timestamp echo) stopped until restart",
      client_source_name(*locked_), client_source_name(source));
  return false;
}

}  // namespace ocp
