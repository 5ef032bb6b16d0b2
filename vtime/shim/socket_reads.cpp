// Blocking reads of an OCP socket, on the simulator's clock (docs/virtual-time.md). A reader
// thread that sits in recv() on its connection (the two-thread vendor client) waits for the
// simulator's bytes like a poll does: it says BLOCKED (no deadline), and a delivery pokes it,
// after which it waits until this instant's bytes have arrived. So what it reads, and when it
// answers, does not depend on when the kernel moved the bytes. A read of a non-blocking socket
// (or with MSG_DONTWAIT), and every other descriptor, goes to libc unchanged. SO_RCVTIMEO is
// not looked at: such a read waits without a deadline.
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include "shim_core.hpp"

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {

namespace {   // this file's libc functions
ssize_t (*real_read)(int, void*, size_t);
ssize_t (*real_readv)(int, const iovec*, int);
ssize_t (*real_recv)(int, void*, size_t, int);
ssize_t (*real_recvfrom)(int, void*, size_t, int, sockaddr*, socklen_t*);
ssize_t (*real_recvmsg)(int, msghdr*, int);
int (*real_poll)(pollfd*, nfds_t, int);
}  // namespace


// Waits on virtual time until `fd` is readable, when it is a blocking OCP socket.
void await_readable(int fd, int flags) {
  if (!active || (flags & MSG_DONTWAIT) || !is_tagged(fd)) return;
  const int mode = fcntl(fd, F_GETFL);
  if (mode < 0 || (mode & O_NONBLOCK)) return;
  pollfd readable{fd, POLLIN, 0};
  (void)virtual_wait(WaitKind::read, no_deadline, &readable, 1, nullptr, [&] {
    readable.revents = 0;
    return REAL(poll)(&readable, 1, 0);
  });
}

}  // namespace ocp_vtime_shim

using namespace ocp_vtime_shim;

extern "C" {

ssize_t read(int fd, void* data, size_t size) {
  await_readable(fd, 0);
  return REAL(read)(fd, data, size);
}
ssize_t readv(int fd, const iovec* parts, int count) {
  await_readable(fd, 0);
  return REAL(readv)(fd, parts, count);
}
ssize_t recv(int fd, void* data, size_t size, int flags) {
  await_readable(fd, flags);
  return REAL(recv)(fd, data, size, flags);
}
ssize_t recvfrom(int fd, void* data, size_t size, int flags, sockaddr* from, socklen_t* length) {
  await_readable(fd, flags);
  return REAL(recvfrom)(fd, data, size, flags, from, length);
}
ssize_t recvmsg(int fd, msghdr* message, int flags) {
  await_readable(fd, flags);
  return REAL(recvmsg)(fd, message, flags);
}

// The _FORTIFY_SOURCE forms.
ssize_t __read_chk(int fd, void* data, size_t size, size_t) { return read(fd, data, size); }
ssize_t __recv_chk(int fd, void* data, size_t size, size_t, int flags) { return recv(fd, data, size, flags); }
ssize_t __recvfrom_chk(int fd, void* data, size_t size, size_t, int flags, sockaddr* from, socklen_t* length) {
  return recvfrom(fd, data, size, flags, from, length);
}

}  // extern "C"
