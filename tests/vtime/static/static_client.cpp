// A statically linked program: LD_PRELOAD cannot reach it, so it cannot live in virtual time
// (the virtual-time tests expect it to be refused within the handshake timeout).
#include <unistd.h>

#include <cstdio>
#include <cstring>

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::puts("usage: vtime_static_client\n  a static binary that only waits, for the tests that refuse it in virtual time");
    return 0;
  }
  if (argc > 1) {
    std::fprintf(stderr, "vtime_static_client: takes no arguments (unknown option %s)\n", argv[1]);
    return 2;
  }
  for (;;) pause();
}
