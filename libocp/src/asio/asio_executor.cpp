#include "ocp/asio_executor.hpp"

// Implementation pending (issue #2, runtime helper).
