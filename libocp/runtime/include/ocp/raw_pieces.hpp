#pragma once
// Conformance testing (both servers: StreamerCore::write_raw_to_vehicle and
// PlayerCore::write_raw_to_client): bytes written exactly as given, cut into pieces that go
// out a chosen delay apart, so a suite can show a client a frame split at any byte boundary
// over a real socket. Protocol code never uses this; it always sends whole frames.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/executor.hpp"
#include "ocp/framed_connection.hpp"

namespace ocp {

// Writes `bytes` to `connection`: the first piece at once (its status is returned), piece i
// `gap`·i later on `executor`. Pieces end at each cut that is inside the bytes and after the
// previous one (others are ignored), and at the end. A later piece goes to the same
// connection while it is open, or nowhere: never into a connection that replaced it.
[[nodiscard]] Status write_raw_in_pieces(Executor& executor, const std::shared_ptr<FramedConnection>& connection,
                                         std::string bytes, const std::vector<std::size_t>& cuts, Micros gap);

}  // namespace ocp
