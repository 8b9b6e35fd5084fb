#include "fabkit/core/file_io.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <system_error>
#include <variant>

namespace fabkit {

namespace fs = std::filesystem;

std::optional<std::string> read_input_file(const fs::path& path,
                                           std::string_view what,
                                           Diagnostics& diags,
                                           std::size_t max_bytes) {
  const std::string name = path.string();
  auto fail = [&](std::string reason) -> std::optional<std::string> {
    diags.error(codes::kUnreadableFile,
                fmt::format("cannot read {} '{}': {}", what, name, reason),
                SourceLocation{name, 0, 0});
    return std::nullopt;
  };
  // O_NONBLOCK: opening a FIFO with no writer must not hang; the fstat below refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT) return fail("no such file");
    if (err == EISDIR) return fail("it is a directory");
    return fail(std::strerror(err));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return fail(std::strerror(errno));
  if (S_ISDIR(st.st_mode)) return fail("it is a directory");
  if (!S_ISREG(st.st_mode)) return fail("it is not a regular file (a device, FIFO or socket)");
  if (static_cast<std::size_t>(st.st_size) > max_bytes) {
    return fail(fmt::format("it is {} bytes; input files may be at most {} bytes",
                            static_cast<long long>(st.st_size),
                            max_bytes));
  }
  // Back to blocking reads for a regular file.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string bytes;
  bytes.resize(static_cast<std::size_t>(st.st_size));
  std::size_t got = 0;
  // The file may grow while it is read: never read past the cap.
  while (true) {
    if (got == bytes.size()) {
      if (bytes.size() > max_bytes) {
        return fail(fmt::format("it is larger than {} bytes", max_bytes));
      }
      bytes.resize(std::min(max_bytes + 1, bytes.size() + 65536));
    }
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail(std::strerror(errno));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  if (got > max_bytes) return fail(fmt::format("it is larger than {} bytes", max_bytes));
  return bytes;
}

namespace {

std::string random_suffix() {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  return fmt::format("{:016x}", rng());
}

}  // namespace

namespace {

// Where bytes written to `path` really go: the path itself, or the target of a link that
// stays in the same directory. Anything but a regular file there is refused (the reason is
// returned) rather than replaced.
std::variant<fs::path, std::string> output_destination(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return path;
  if (S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const fs::path target = fs::weakly_canonical(path, ec);
    const fs::path dir =
        fs::weakly_canonical(path.parent_path().empty() ? "." : path.parent_path(), ec);
    if (ec || target.parent_path() != dir) {
      return std::string("it is a symbolic link that points out of its directory; remove it first");
    }
    if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
      return std::string("it links to something that is not a regular file");
    }
    return target;
  }
  if (S_ISDIR(st.st_mode)) return std::string("it is a directory");
  if (!S_ISREG(st.st_mode))
    return std::string("it is not a regular file (a FIFO, device or socket)");
  return path;
}

void refuse_output(const fs::path& path, std::string_view why, int err, Diagnostics& diags) {
  const std::string name = path.string();
  diags.error(codes::kWriteFailed,
              fmt::format("cannot write '{}': {}{}{}",
                          name,
                          why,
                          err != 0 ? ": " : "",
                          err != 0 ? std::strerror(err) : ""),
              SourceLocation{name, 0, 0});
}

}  // namespace

bool outputs_writable(std::span<const fs::path> paths, Diagnostics& diags) {
  bool ok = true;
  for (const fs::path& path : paths) {
    const auto where = output_destination(path);
    if (const auto* why = std::get_if<std::string>(&where)) {
      refuse_output(path, *why, 0, diags);
      ok = false;
    }
  }
  return ok;
}

bool write_file_atomically(const fs::path& path, std::string_view bytes, Diagnostics& diags) {
  fs::path tmp;
  auto fail = [&](std::string_view what, int err) {
    if (!tmp.empty()) ::unlink(tmp.c_str());
    refuse_output(path, what, err, diags);
    return false;
  };

  auto where = output_destination(path);
  if (const auto* why = std::get_if<std::string>(&where)) return fail(*why, 0);
  const fs::path destination = std::get<fs::path>(std::move(where));

  // A fresh temporary beside the destination, created exclusively (never through a link).
  int fd = -1;
  for (int attempt = 0; attempt < 8 && fd < 0; ++attempt) {
    tmp = destination;
    tmp += ".tmp-" + random_suffix();
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    const int err = errno;
    tmp.clear();
    return fail(
        fmt::format("cannot create a temporary file in '{}'",
                    destination.parent_path().empty() ? "." : destination.parent_path().string()),
        err);
  }
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      return fail("write error", err);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) return fail("write error", errno);
  if (::rename(tmp.c_str(), destination.c_str()) != 0) {
    return fail(fmt::format("cannot rename '{}'", tmp.string()), errno);
  }
  return true;
}

bool make_output_directory(const fs::path& directory, Diagnostics& diags) {
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec || !fs::is_directory(directory, ec)) {
    diags.error(codes::kWriteFailed,
                fmt::format("cannot create output directory '{}': {}",
                            directory.string(),
                            ec ? ec.message() : "a file of that name is in the way"),
                SourceLocation{directory.string(), 0, 0});
    return false;
  }
  return true;
}

}  // namespace fabkit
