#include "input/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <stdexcept>
#include <unistd.h>

namespace liftcheck {

void write_file_atomic(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  const auto fail = [&](const char* doing) {
    const int err = errno;
    ::unlink(tmp.c_str());
    return std::runtime_error(fmt::format("cannot write '{}': {} ({})", path.string(), std::strerror(err), doing));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), std::strerror(err)));
  }
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t put = ::write(fd, text.data() + done, text.size() - done);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      if (put == 0) errno = EIO;
      const auto e = fail("writing");
      ::close(fd);
      throw e;
    }
    done += static_cast<std::size_t>(put);
  }
  if (::close(fd) != 0) throw fail("closing");
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw fail("renaming into place");
}

}  // namespace liftcheck
