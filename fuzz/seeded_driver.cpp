// The fuzz harnesses' driver in the ordinary (g++, Release) build, so that every harness runs in
// ctest on every build: a seeded mutation fuzzer, deterministic for a given seed, bounded by a
// number of inputs and a time budget. It runs each seed file as it is, then mutated copies
// (bit flips, byte and token insertions, deletions, duplicated ranges, splices of two seeds).
// libFuzzer (./scripts/sanitize, clang) drives the same harnesses with coverage feedback.
//
//   <harness> [--seed N] [--runs N] [--seconds S] [--max-len BYTES] [--slow-ms MS]
//             [--keep DIR] SEED_FILE_OR_DIR...
//   <harness> FILE              (one input only: reproduces a finding)
//
// An input that crashes, breaks a harness's invariant (they abort) or hangs (--hang-s, 10 s)
// is written to DIR/finding-<seed>-<run> (--keep, default the working directory) before the
// process dies, and the run fails.
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

// What a signal handler writes when the process dies: the input being run (set before each).
const Bytes* g_current = nullptr;
char g_finding_path[4096] = "finding";

void write_finding_and_die(int signal_number) {
  if (g_current != nullptr) {
    const int fd = ::open(g_finding_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      const std::uint8_t* p = g_current->data();
      std::size_t left = g_current->size();
      while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n <= 0) break;
        p += n;
        left -= static_cast<std::size_t>(n);
      }
      ::close(fd);
    }
    static const char kMsg[] = "\nfuzz: the input that failed was written to ";
    (void)!::write(2, kMsg, sizeof kMsg - 1);
    (void)!::write(2, g_finding_path, std::strlen(g_finding_path));
    (void)!::write(2, "\n", 1);
  }
  if (signal_number == SIGALRM) {
    static const char kHang[] = "fuzz: an input ran longer than the hang limit\n";
    (void)!::write(2, kHang, sizeof kHang - 1);
  }
  ::signal(signal_number == SIGALRM ? SIGABRT : signal_number, SIG_DFL);
  ::raise(signal_number == SIGALRM ? SIGABRT : signal_number);
}

bool read_file(const std::filesystem::path& path, Bytes& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

// Tokens that matter to the readers (YAML structure, numbers at their limits, bad UTF-8,
// HTTP framing), inserted whole: random bytes rarely form them.
constexpr std::array<std::string_view, 40> kTokens = {": ",
                                                      "\n- ",
                                                      "\n  ",
                                                      "[",
                                                      "]",
                                                      "{",
                                                      "}",
                                                      ",",
                                                      "'",
                                                      "\"",
                                                      "&a ",
                                                      "*a",
                                                      "!!str ",
                                                      "#",
                                                      "~",
                                                      "null",
                                                      "-1",
                                                      "0",
                                                      "1e308",
                                                      "-1e308",
                                                      "nan",
                                                      ".inf",
                                                      "-.inf",
                                                      "4294967297",
                                                      "\xff",
                                                      "\xc3",
                                                      "\xed\xa0\x80",
                                                      "\x00",
                                                      "\r\n",
                                                      "\r\n\r\n",
                                                      "0\r\n\r\n",
                                                      "Transfer-Encoding: chunked\r\n",
                                                      "Content-Length: 99999999\r\n",
                                                      "../",
                                                      "/etc/passwd",
                                                      "part_files: [x]\n",
                                                      "fabkit: ",
                                                      "connect: ",
                                                      "%",
                                                      "\t"};

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::size_t below(std::size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }

  Bytes mutate(const Bytes& seed, const Bytes& other, std::size_t max_len) {
    Bytes b = seed;
    const std::size_t edits = 1 + below(below(8) + 1);
    for (std::size_t e = 0; e < edits; ++e) edit(b, other);
    if (b.size() > max_len) b.resize(max_len);
    return b;
  }

 private:
  void edit(Bytes& b, const Bytes& other) {
    const std::size_t at = below(b.size() + 1);
    switch (below(9)) {
      case 0:  // flip a bit
        if (!b.empty()) b[below(b.size())] ^= static_cast<std::uint8_t>(1u << below(8));
        break;
      case 1:  // a random byte
        if (!b.empty()) b[below(b.size())] = static_cast<std::uint8_t>(below(256));
        break;
      case 2: {  // insert random bytes
        const std::size_t n = 1 + below(8);
        Bytes r(n);
        for (auto& x : r) x = static_cast<std::uint8_t>(below(256));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), r.begin(), r.end());
        break;
      }
      case 3:
      case 4: {  // insert a token
        const std::string_view t = kTokens[below(kTokens.size())];
        const std::size_t n = t.empty() ? 1 : t.size();  // "\x00" has size 0 as a literal
        const char* p = t.empty() ? "\0" : t.data();
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), p, p + n);
        break;
      }
      case 5: {  // delete a range
        if (b.empty()) break;
        const std::size_t from = below(b.size());
        const std::size_t n = 1 + below(std::min<std::size_t>(64, b.size() - from));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(from),
                b.begin() + static_cast<std::ptrdiff_t>(from + n));
        break;
      }
      case 6: {  // duplicate a range (repeated lines, deeper nesting)
        if (b.empty()) break;
        const std::size_t from = below(b.size());
        const std::size_t n = 1 + below(std::min<std::size_t>(256, b.size() - from));
        const Bytes copy(b.begin() + static_cast<std::ptrdiff_t>(from),
                         b.begin() + static_cast<std::ptrdiff_t>(from + n));
        const std::size_t times = 1 + below(4);
        for (std::size_t k = 0; k < times; ++k)
          b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), copy.begin(), copy.end());
        break;
      }
      case 7: {  // splice: a range of another seed
        if (other.empty()) break;
        const std::size_t from = below(other.size());
        const std::size_t n = 1 + below(std::min<std::size_t>(512, other.size() - from));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at),
                 other.begin() + static_cast<std::ptrdiff_t>(from),
                 other.begin() + static_cast<std::ptrdiff_t>(from + n));
        break;
      }
      default: {  // change a digit (sizes, counts, coordinates)
        std::vector<std::size_t> digits;
        for (std::size_t i = 0; i < b.size(); ++i)
          if (b[i] >= '0' && b[i] <= '9') digits.push_back(i);
        if (!digits.empty()) b[digits[below(digits.size())]] = "0123456789"[below(10)];
        break;
      }
    }
  }

  std::mt19937_64 rng_;
};

int usage() {
  std::fprintf(stderr,
               "usage: harness [--seed N] [--runs N] [--seconds S] [--max-len BYTES] "
               "[--hang-s S] [--keep DIR] SEED_FILE_OR_DIR...\n"
               "       harness FILE   (run one input)\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1;
  long long runs = 1'000'000;
  double seconds = 3;
  std::size_t max_len = 64 << 10;
  unsigned hang_s = 10;
  std::filesystem::path keep = ".";
  std::vector<std::filesystem::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    const char* v = nullptr;
    if (a == "--seed" && (v = value())) {
      seed = std::strtoull(v, nullptr, 10);
    } else if (a == "--runs" && (v = value())) {
      runs = std::atoll(v);
    } else if (a == "--seconds" && (v = value())) {
      seconds = std::atof(v);
    } else if (a == "--max-len" && (v = value())) {
      max_len = static_cast<std::size_t>(std::atoll(v));
    } else if (a == "--hang-s" && (v = value())) {
      hang_s = static_cast<unsigned>(std::atoi(v));
    } else if (a == "--keep" && (v = value())) {
      keep = v;
    } else if (a.rfind("--", 0) == 0) {
      return usage();
    } else {
      inputs.emplace_back(a);
    }
  }
  if (inputs.empty()) return usage();
  std::error_code keep_error;
  std::filesystem::create_directories(keep, keep_error);

  ::signal(SIGABRT, write_finding_and_die);
  ::signal(SIGSEGV, write_finding_and_die);
  ::signal(SIGBUS, write_finding_and_die);
  ::signal(SIGFPE, write_finding_and_die);
  ::signal(SIGILL, write_finding_and_die);
  ::signal(SIGALRM, write_finding_and_die);

  std::vector<Bytes> seeds;
  std::vector<std::string> seed_names;
  for (const auto& in : inputs) {
    std::error_code ec;
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(in, ec)) {
      for (const auto& e : std::filesystem::directory_iterator(in, ec))
        if (e.is_regular_file()) files.push_back(e.path());
      std::sort(files.begin(), files.end());  // the order, and so the run, is deterministic
    } else {
      files.push_back(in);
    }
    for (const auto& f : files) {
      Bytes b;
      if (!read_file(f, b)) {
        std::fprintf(stderr, "fuzz: cannot read %s\n", f.string().c_str());
        return 1;
      }
      seeds.push_back(std::move(b));
      seed_names.push_back(f.filename().string());
    }
  }
  if (seeds.empty()) {
    std::fprintf(stderr, "fuzz: no seed files in the given directories\n");
    return 1;
  }

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto stop =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  double slowest_ms = 0;
  std::string slowest = "-";
  auto run_one = [&](const Bytes& input, const std::string& name) {
    g_current = &input;
    std::snprintf(g_finding_path,
                  sizeof g_finding_path,
                  "%s/finding-%llu-%s",
                  keep.string().c_str(),
                  static_cast<unsigned long long>(seed),
                  name.c_str());
    ::alarm(hang_s);
    const auto t0 = Clock::now();
    LLVMFuzzerTestOneInput(input.data(), input.size());
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    ::alarm(0);
    if (ms > slowest_ms) {
      slowest_ms = ms;
      slowest = name;
    }
  };

  // Every seed as it is, then mutants until the budget is spent.
  for (std::size_t i = 0; i < seeds.size(); ++i) run_one(seeds[i], seed_names[i]);
  if (inputs.size() == 1 && seeds.size() == 1 && !std::filesystem::is_directory(inputs[0])) {
    std::printf("fuzz: ran %s (%.1f ms)\n", seed_names[0].c_str(), slowest_ms);
    return 0;
  }
  Mutator mutator(seed);
  long long done = 0;
  while (done < runs && Clock::now() < stop) {
    const std::size_t s = mutator.below(seeds.size());
    const std::size_t o = mutator.below(seeds.size());
    const Bytes input = mutator.mutate(seeds[s], seeds[o], max_len);
    run_one(input, "run" + std::to_string(done) + "-of-" + seed_names[s]);
    ++done;
  }
  g_current = nullptr;
  const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("fuzz: %zu seeds and %lld mutants (seed %llu) in %.1f s; slowest %.1f ms (%s)\n",
              seeds.size(),
              done,
              static_cast<unsigned long long>(seed),
              total_s,
              slowest_ms,
              slowest.c_str());
  return 0;
}
