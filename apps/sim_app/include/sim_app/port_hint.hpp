#pragma once
// A listen error says what to do about a busy port: which option of this program moves that
// port. Every port a simulator opens has its own option, so the hint is given where the port
// is opened, not guessed afterwards.
#include <fmt/format.h>

#include <string_view>
#include <system_error>

#include "ocp/error.hpp"

namespace ocp::sim_app {

[[nodiscard]] inline Status with_port_hint(Status status, std::string_view program, std::string_view option) {
  if (status || status.error().code != std::errc::address_in_use) return status;
  Error error = status.error();
  error.detail += fmt::format(" (is another {} running? pick another port with {})", program, option);
  return error;
}

}  // namespace ocp::sim_app
