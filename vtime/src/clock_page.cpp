// The clock page's delivery counts (clock_page.hpp).
#include "clock_page.hpp"

namespace ocp::vtime {

bool claim_delivery_slot(ClockPage& page, std::uint16_t port) {
  const std::uint32_t used = page.connections.load();
  for (std::uint32_t i = 0; i < used; ++i) {
    if (page.delivered[i].port.load() == 0) {
      page.delivered[i].delivered.store(0);
      page.delivered[i].port.store(port);
      return true;
    }
  }
  if (used >= static_cast<std::uint32_t>(max_connections)) return false;
  page.delivered[used].delivered.store(0);
  page.delivered[used].port.store(port);
  page.connections.store(used + 1, std::memory_order_release);
  return true;
}

void release_delivery_slot(ClockPage& page, std::uint16_t port) {
  const std::uint32_t used = page.connections.load();
  for (std::uint32_t i = 0; i < used; ++i) {
    if (page.delivered[i].port.load() == port) page.delivered[i].port.store(0);
  }
}

void publish_delivered(ClockPage& page, std::uint16_t port, std::uint64_t total) {
  const std::uint32_t used = page.connections.load();
  for (std::uint32_t i = 0; i < used; ++i) {
    if (page.delivered[i].port.load() == port) page.delivered[i].delivered.store(total, std::memory_order_release);
  }
}

}  // namespace ocp::vtime
