#pragma once
// In-memory duplex byte pipe driven by an Executor. Bytes written on one end are delivered
// to the other end's on_bytes via the executor (after `one_way_delay`), in order, optionally
// split into chunks of at most `max_chunk_bytes` (to exercise incremental decoders).
#include <cstddef>
#include <memory>
#include <string>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"

namespace ocp {

struct PipeOptions {
  Micros one_way_delay{0};
  std::size_t max_chunk_bytes = 0;   // 0 = deliver each write as one chunk
  std::string name_a = "pipe:a";     // peer name as seen from end b
  std::string name_b = "pipe:b";     // peer name as seen from end a
};

struct PipeEnds {
  std::shared_ptr<ByteStream> a;
  std::shared_ptr<ByteStream> b;
};

PipeEnds make_pipe(Executor& executor, PipeOptions options = {});

}  // namespace ocp
