#include "ocp/bounded_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>

namespace ocp {
namespace {

std::atomic<std::uint64_t> raised_cap{0};

Error file_error(const std::string& path, const std::string& reason) {
  return Error{std::make_error_code(std::errc::invalid_argument), path + ": " + reason};
}

const char* file_type_name(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string too_large(const FileKind& kind, std::uint64_t cap, const std::string& size) {
  std::string text = size + "; a " + kind.name + " may be at most " + std::to_string(cap) + " bytes";
  if (kind.raise_with[0] != '\0') text += std::string(" (raise with ") + kind.raise_with + ")";
  return text;
}

// Closes the descriptor on every path.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

void raise_file_caps(std::uint64_t bytes) { raised_cap.store(bytes); }

std::uint64_t file_cap(const FileKind& kind) {
  if (kind.raise_with[0] == '\0') return kind.max_bytes;
  const std::uint64_t raised = raised_cap.load();
  return raised > kind.max_bytes ? raised : kind.max_bytes;
}

Result<std::string> read_bounded_file(const std::string& path, const FileKind& kind) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (file.fd < 0) return file_error(path, std::string("cannot open the ") + kind.name + ": " + std::strerror(errno));
  struct stat status {};
  if (::fstat(file.fd, &status) != 0) {
    return file_error(path, std::string("cannot read the ") + kind.name + ": " + std::strerror(errno));
  }
  if (!S_ISREG(status.st_mode)) {
    return file_error(path, std::string("a ") + kind.name + " must be a regular file, not " + file_type_name(status.st_mode));
  }
  const std::uint64_t cap = file_cap(kind);
  const auto size = static_cast<std::uint64_t>(status.st_size);
  if (size > cap) return file_error(path, too_large(kind, cap, std::to_string(size) + " bytes"));
  std::string text;
  text.resize(static_cast<std::size_t>(size) + 1);   // one more: a file that grew since fstat is caught
  std::size_t used = 0;
  for (;;) {
    if (used == text.size()) {
      if (used > cap) return file_error(path, too_large(kind, cap, "more than " + std::to_string(cap) + " bytes"));
      text.resize(std::min<std::uint64_t>(cap + 1, used * 2 + 4096));
    }
    const ssize_t n = ::read(file.fd, text.data() + used, text.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return file_error(path, std::string("cannot read the ") + kind.name + ": " + std::strerror(errno));
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  if (used > cap) return file_error(path, too_large(kind, cap, "more than " + std::to_string(cap) + " bytes"));
  text.resize(used);
  return text;
}

}  // namespace ocp
