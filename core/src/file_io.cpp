#include "fabkit/core/file_io.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

namespace fabkit {

namespace fs = std::filesystem;

bool write_file_atomically(const fs::path& path, std::string_view bytes, Diagnostics& diags) {
  const std::string name = path.string();
  fs::path tmp = path;
  tmp += ".tmp";
  auto fail = [&](std::string_view what, int err) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    diags.error(DiagnosticCode::kUnreadableFile,
                fmt::format("cannot write '{}': {}{}{}",
                            name,
                            what,
                            err != 0 ? ": " : "",
                            err != 0 ? std::strerror(err) : ""),
                SourceLocation{name, 0, 0});
    return false;
  };

  errno = 0;
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) return fail(fmt::format("cannot create '{}'", tmp.string()), errno);
  errno = 0;
  const std::size_t written = bytes.empty() ? 0 : std::fwrite(bytes.data(), 1, bytes.size(), f);
  int err = errno;
  const bool write_ok = written == bytes.size() && std::fflush(f) == 0;
  if (!write_ok && err == 0) err = errno;
  errno = 0;
  const bool close_ok = std::fclose(f) == 0;
  if (!write_ok) return fail("write error", err);
  if (!close_ok) return fail("write error", errno);

  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) return fail(fmt::format("cannot rename '{}': {}", tmp.string(), ec.message()), 0);
  return true;
}

}  // namespace fabkit
