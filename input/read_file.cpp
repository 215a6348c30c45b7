#include "input/read_file.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include "input/interrupt.hpp"
#include "input/params.hpp"
#include "input/trace.hpp"

namespace liftcheck {

namespace {

/// Closes the descriptor however the read ends.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string size_text(std::size_t bytes) {
  if (bytes >= (std::size_t{1} << 20) && bytes % (std::size_t{1} << 20) == 0) return fmt::format("{} MiB", bytes >> 20);
  return fmt::format("{} bytes", bytes);
}

std::string read_text_file(const std::filesystem::path& path, std::size_t max_bytes, const std::string& what) {
  const std::string name = printable(path.string(), 200);
  // Not blocking at the open (a FIFO without a writer), blocking reads afterwards: a signal
  // interrupts them (the handler is installed without SA_RESTART).
  Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK)};
  if (f.fd < 0) throw InputError(fmt::format("cannot read {} '{}': {}", what, name, std::strerror(errno)));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0)
    throw InputError(fmt::format("cannot read {} '{}': {}", what, name, std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) throw InputError(fmt::format("{} '{}' is a folder, not a file", what, name));
  const auto too_big = [&] {
    return InputError(fmt::format("{} '{}' is larger than the limit of {} for a {} (stopped reading there)", what, name,
                                  size_text(max_bytes), what));
  };
  if (S_ISREG(st.st_mode) && static_cast<std::size_t>(st.st_size) > max_bytes) throw too_big();
  ::fcntl(f.fd, F_SETFL, ::fcntl(f.fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  // Room for the last read too (it finds the end): a file of 300 MB is never copied to grow.
  if (S_ISREG(st.st_mode)) text.reserve(static_cast<std::size_t>(st.st_size) + kChunk);
  for (;;) {
    throw_if_interrupted_by([&] { return fmt::format("while reading '{}'", name); });
    const std::size_t room = std::min(kChunk, max_bytes + 1 - text.size());
    const std::size_t at = text.size();
    text.resize(at + room);
    const ssize_t got = ::read(f.fd, text.data() + at, room);
    if (got < 0) {
      text.resize(at);
      if (errno == EINTR) continue;
      throw InputError(fmt::format("cannot read {} '{}': {}", what, name, std::strerror(errno)));
    }
    text.resize(at + static_cast<std::size_t>(got));
    if (got == 0) break;
    if (text.size() > max_bytes) throw too_big();
  }
  return text;
}

bool is_utf8(const std::string& s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = p[i];
    std::size_t len = 0;
    unsigned min = 0, cp = 0;
    if (c < 0x80)
      len = 1, cp = c;
    else if ((c & 0xE0) == 0xC0)
      len = 2, cp = c & 0x1F, min = 0x80;
    else if ((c & 0xF0) == 0xE0)
      len = 3, cp = c & 0x0F, min = 0x800;
    else if ((c & 0xF8) == 0xF0)
      len = 4, cp = c & 0x07, min = 0x10000;
    else
      return false;
    if (i + len > n) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((p[i + k] & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (p[i + k] & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += len;
  }
  return true;
}

void require_utf8(const std::string& text, const std::string& what) {
  if (!is_utf8(text))
    throw InputError(
        fmt::format("{} '{}' is not valid UTF-8: liftcheck records names in JSON, which holds UTF-8 only (rename it)",
                    what, printable(text, 200)));
}

}  // namespace liftcheck
