// fabkit: starts the program that holds what a command needs. A hacks command — solve, demo,
// parts, and check or build of a hacks design — runs in fabkit-hacks, which loads only the hacks
// kit and its libraries (the process starts in about 3 ms instead of 11: the other kits bring
// lib3MF, OpenSSL, IPOPT with MUMPS and SQLite, docs/benchmarks.md); everything else runs in
// fabkit-all, which holds every kit. Both sit next to this program. Where a command's kit is
// not plainly hacks (no readable design, another or no `fabkit:` header, help, version), it
// goes to fabkit-all, which says what is wrong.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

namespace {

// The value of a `fabkit:` header of the regular file at `path` ("hacks/1"), empty if it has
// none before its first other key or is not a regular file (opened without blocking and
// checked before it is read: a FIFO must not hang the launcher).
std::string kit_header(const char* path) {
  struct stat st {};
  if (path[0] == '-' || stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return {};
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return {};
  char buffer[4096];
  ssize_t n = 0;
  if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) n = read(fd, buffer, sizeof buffer);
  close(fd);
  if (n <= 0) return {};
  const std::string_view text(buffer, static_cast<std::size_t>(n));
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    constexpr std::string_view kKey = "fabkit: ";
    if (line.substr(0, kKey.size()) != kKey) return {};
    return std::string(line.substr(kKey.size()));
  }
  return {};
}

// Whether the command can run in fabkit-hacks.
bool hacks_command(int argc, char** argv) {
  if (argc < 2) return false;
  const std::string_view command = argv[1];
  if (command == "demo" || command == "parts") return true;
  if (command != "solve" && command != "check" && command != "build") return false;
  // Every file named that has a `fabkit:` header must be a hacks file, and one must be.
  bool hacks = false;
  for (int i = 2; i < argc; ++i) {
    const std::string kit = kit_header(argv[i]);
    if (kit.empty()) continue;
    if (kit != "hacks/1") return false;
    hacks = true;
  }
  return hacks;
}

// The directory this program was started from (its real path), with a trailing '/'.
std::string own_directory() {
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return {};
  std::string dir(path, static_cast<std::size_t>(n));
  return dir.substr(0, dir.rfind('/') + 1);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string program =
      own_directory() + (hacks_command(argc, argv) ? "fabkit-hacks" : "fabkit-all");
  execv(program.c_str(), argv);
  std::fprintf(stderr, "error: cannot start %s: %s\n", program.c_str(), std::strerror(errno));
  return 8;  // an internal error: the installation is incomplete
}
