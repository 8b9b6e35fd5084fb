// Reading input files and writing outputs safely (core/file_io.h), and text made safe to echo
// (core/text.h): special files refused without blocking, the size cap, atomic writes that
// never replace a FIFO, a device or a link out of their directory and leave no temporary.
#include "fabkit/core/file_io.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "fabkit/core/text.h"

namespace fabkit {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class FileIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fabkit_file_io_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, ec);
    fs::remove_all(dir_, ec);
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  // Files in dir_ other than `except`: temporaries left behind.
  int files_besides(const std::set<std::string>& except) const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_)) {
      n += except.count(e.path().filename().string()) ? 0 : 1;
    }
    return n;
  }
  fs::path dir_;
};

TEST_F(FileIo, ReadsRegularFilesWhole) {
  std::ofstream(dir_ / "a.yaml") << "fabkit: hacks/1\n";
  Diagnostics d;
  const auto text = read_input_file(dir_ / "a.yaml", "design file", d);
  ASSERT_TRUE(text) << d.format();
  EXPECT_EQ(*text, "fabkit: hacks/1\n");
  EXPECT_TRUE(d.empty());
}

TEST_F(FileIo, RefusesSpecialFilesWithoutBlocking) {
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  const auto started = Clock::now();
  for (const fs::path& p : {dir_ / "fifo", fs::path("/dev/zero"), dir_, dir_ / "missing"}) {
    Diagnostics d;
    EXPECT_FALSE(read_input_file(p, "design file", d)) << p;
    ASSERT_TRUE(d.has_errors()) << p;
    EXPECT_EQ(d.items().front().code, codes::kUnreadableFile);
    EXPECT_NE(d.items().front().message.find("design file"), std::string::npos);
    EXPECT_NE(d.items().front().message.find(p.string()), std::string::npos);
  }
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - started).count(), 2.0);
  Diagnostics d;
  read_input_file("/dev/zero", "design file", d);
  EXPECT_NE(d.format().find("not a regular file"), std::string::npos) << d.format();
}

TEST_F(FileIo, RefusesFilesPastTheCap) {
  { std::ofstream f(dir_ / "big.yaml"); }
  fs::resize_file(dir_ / "big.yaml", kMaxInputFileBytes + 1);
  Diagnostics d;
  EXPECT_FALSE(read_input_file(dir_ / "big.yaml", "design file", d));
  EXPECT_NE(d.format().find("at most 16777216 bytes"), std::string::npos) << d.format();
  std::ofstream(dir_ / "small.yaml") << std::string(100, 'x');
  Diagnostics e;
  EXPECT_FALSE(read_input_file(dir_ / "small.yaml", "part file", e, 99));
  EXPECT_TRUE(read_input_file(dir_ / "small.yaml", "part file", e, 100));
}

TEST_F(FileIo, WritesWholeFilesAndReplacesThemAtomically) {
  Diagnostics d;
  ASSERT_TRUE(write_file_atomically(dir_ / "out.json", "first", d)) << d.format();
  EXPECT_EQ(slurp(dir_ / "out.json"), "first");
  // An open reader of the old file keeps reading the old bytes: the new file is a new inode.
  std::ifstream old_reader(dir_ / "out.json");
  ASSERT_TRUE(write_file_atomically(dir_ / "out.json", std::string(1 << 20, 'n'), d));
  std::string seen;
  old_reader >> seen;
  EXPECT_EQ(seen, "first");
  EXPECT_EQ(fs::file_size(dir_ / "out.json"), std::size_t{1} << 20);
  EXPECT_EQ(files_besides({"out.json"}), 0) << "a temporary was left behind";
}

TEST_F(FileIo, NeverReplacesAFifoADeviceOrADirectory) {
  ASSERT_EQ(::mkfifo((dir_ / "result.json").c_str(), 0600), 0);
  fs::create_directory(dir_ / "scene.glb");
  fs::create_symlink("/dev/null", dir_ / "model.stl");
  for (const char* name : {"result.json", "scene.glb", "model.stl"}) {
    Diagnostics d;
    EXPECT_FALSE(write_file_atomically(dir_ / name, "bytes", d)) << name;
    ASSERT_TRUE(d.has_errors());
    EXPECT_EQ(d.items().front().code, codes::kWriteFailed);
    EXPECT_NE(d.items().front().message.find(name), std::string::npos) << d.format();
  }
  struct stat st {};
  ASSERT_EQ(::stat((dir_ / "result.json").c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_TRUE(fs::is_directory(dir_ / "scene.glb"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "model.stl"));
  EXPECT_EQ(files_besides({"result.json", "scene.glb", "model.stl"}), 0);
}

TEST_F(FileIo, LinksAreWrittenThroughOnlyWithinTheirDirectory) {
  fs::create_directories(dir_ / "out");
  fs::create_directories(dir_ / "elsewhere");
  std::ofstream(dir_ / "elsewhere" / "victim") << "keep me";
  fs::create_symlink(dir_ / "elsewhere" / "victim", dir_ / "out" / "report.json");
  Diagnostics d;
  EXPECT_FALSE(write_file_atomically(dir_ / "out" / "report.json", "overwritten", d));
  EXPECT_NE(d.format().find("points out of its directory"), std::string::npos) << d.format();
  EXPECT_EQ(slurp(dir_ / "elsewhere" / "victim"), "keep me");
  // A link to a file beside it (report.json -> report-v2.json) is kept, its target written.
  std::ofstream(dir_ / "out" / "report-v2.json") << "old";
  fs::create_symlink("report-v2.json", dir_ / "out" / "latest.json");
  Diagnostics e;
  ASSERT_TRUE(write_file_atomically(dir_ / "out" / "latest.json", "new", e)) << e.format();
  EXPECT_TRUE(fs::is_symlink(dir_ / "out" / "latest.json"));
  EXPECT_EQ(slurp(dir_ / "out" / "report-v2.json"), "new");
}

TEST_F(FileIo, ASetOfOutputsIsCheckedBeforeAnyIsWritten) {
  fs::create_directories(dir_ / "out");
  fs::create_directories(dir_ / "elsewhere");
  std::ofstream(dir_ / "elsewhere" / "victim") << "keep me";
  fs::create_symlink(dir_ / "elsewhere" / "victim", dir_ / "out" / "result.json");
  ASSERT_EQ(::mkfifo((dir_ / "out" / "scene.glb").c_str(), 0600), 0);
  std::ofstream(dir_ / "out" / "model.stl") << "old";
  const std::vector<fs::path> files{dir_ / "out" / "model.stl",    // a regular file: fine
                                    dir_ / "out" / "result.json",  // a link out: refused
                                    dir_ / "out" / "scene.glb",    // a FIFO: refused
                                    dir_ / "out" / "new.obj"};     // absent: fine
  Diagnostics d;
  EXPECT_FALSE(outputs_writable(files, d));
  EXPECT_EQ(d.size(), 2u) << d.format();
  EXPECT_NE(d.format().find("result.json': it is a symbolic link"), std::string::npos)
      << d.format();
  EXPECT_NE(d.format().find("scene.glb': it is not a regular file"), std::string::npos)
      << d.format();
  EXPECT_FALSE(fs::exists(dir_ / "out" / "new.obj"));  // asking writes nothing
  EXPECT_EQ(slurp(dir_ / "out" / "model.stl"), "old");
  Diagnostics e;
  EXPECT_TRUE(outputs_writable(std::vector<fs::path>{files[0], files[3]}, e)) << e.format();
}

TEST_F(FileIo, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  std::ofstream(dir_ / "bom.csv") << "old";
  // The disk "fills up" half way: a file-size limit makes write() fail with EFBIG.
  struct rlimit saved {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  Diagnostics d;
  const bool ok = write_file_atomically(dir_ / "bom.csv", std::string(1 << 20, 'n'), d);
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, previous);
  EXPECT_FALSE(ok);
  EXPECT_NE(d.format().find("write error"), std::string::npos) << d.format();
  EXPECT_EQ(slurp(dir_ / "bom.csv"), "old");
  EXPECT_EQ(files_besides({"bom.csv"}), 0) << "the temporary was left behind";
  // A directory that cannot be written: refused before anything is written.
  if (::geteuid() != 0) {
    fs::permissions(dir_, fs::perms::owner_read | fs::perms::owner_exec);
    Diagnostics e;
    EXPECT_FALSE(write_file_atomically(dir_ / "bom.csv", "new", e));
    EXPECT_NE(e.format().find("cannot create a temporary file"), std::string::npos);
    fs::permissions(dir_, fs::perms::owner_all);
    EXPECT_EQ(slurp(dir_ / "bom.csv"), "old");
  }
}

TEST_F(FileIo, OutputDirectoriesAreMadeOrRefusedClearly) {
  Diagnostics d;
  EXPECT_TRUE(make_output_directory(dir_ / "a" / "b", d));
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  std::ofstream(dir_ / "file") << "x";
  EXPECT_FALSE(make_output_directory(dir_ / "file", d));
  EXPECT_NE(d.format().find("cannot create output directory"), std::string::npos);
}

TEST(Text, Utf8ValidationAndExcerpts) {
  EXPECT_TRUE(is_valid_utf8("plain ascii"));
  EXPECT_TRUE(is_valid_utf8("Grüße, 日本, 🙂"));
  EXPECT_FALSE(is_valid_utf8("\xff"));
  EXPECT_FALSE(is_valid_utf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(is_valid_utf8("\xed\xa0\x80"));      // a surrogate
  EXPECT_FALSE(is_valid_utf8("\xf4\x90\x80\x80"));  // past U+10FFFF
  EXPECT_FALSE(is_valid_utf8("\xe6\x97"));          // cut short
  const std::string long_name(1'000'000, 'n');
  const std::string e = excerpt(long_name);
  EXPECT_LT(e.size(), 120u);
  EXPECT_NE(e.find("999940 more bytes"), std::string::npos) << e;
  EXPECT_TRUE(
      is_valid_utf8(excerpt("a\xff\xfe"
                            "b")));
  EXPECT_EQ(excerpt("line\nbreak\x01"), "line?break?");
}

TEST(Text, CaseBlindNamesIdentifiersAndXmlText) {
  EXPECT_EQ(ascii_lower("DoubleHook_2"), "doublehook_2");
  EXPECT_EQ(ascii_lower("GRÜN"), "grÜn");  // only ASCII letters change; UTF-8 is kept intact
  EXPECT_TRUE(is_identifier("hook_1"));
  EXPECT_TRUE(is_identifier("_x"));
  EXPECT_FALSE(is_identifier(""));
  EXPECT_FALSE(is_identifier("1hook"));
  EXPECT_FALSE(is_identifier("hook-1"));
  EXPECT_FALSE(is_identifier("h\xc3\xa9"));  // é: identifiers are ASCII
  EXPECT_EQ(xml_escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
  // XML 1.0 allows tab, line feed and carriage return and no other control character.
  EXPECT_EQ(xml_escape("x\x01y\tz\x1f\n\r\x7f"), "xy\tz\n\r\x7f");
}

}  // namespace
}  // namespace fabkit
