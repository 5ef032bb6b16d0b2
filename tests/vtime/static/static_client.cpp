// A statically linked program: LD_PRELOAD cannot reach it, so it cannot live in virtual time
// (the virtual-time tests expect it to be refused within the handshake timeout).
#include <unistd.h>

int main() {
  for (;;) pause();
}
