// SIGINT, SIGTERM or SIGHUP while a file is being written leave no hidden
// temporary file behind (issue 21): a child process opens AtomicFiles,
// writes, and is signalled mid-write; the parent finds the folders clean and
// the child ended by that signal.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "mesh_writers.hpp"
#include "pfill/atomic_file.hpp"

namespace fs = std::filesystem;
using namespace pfill;

namespace {

size_t files_in(const fs::path& folder) {
  size_t n = 0;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) n += entry.is_regular_file();
  return n;
}

}  // namespace

TEST_CASE("a signal while writing removes the temporary files, then ends the process by that signal") {
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    CAPTURE(signal_number);
    test::TempDir dir("signal");
    const fs::path folder = dir.file("out"), frames = dir.file("out/frames");
    fs::create_directories(frames);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      remove_temporary_files_on_signals();
      AtomicFile particles(folder / "particles.ply");
      AtomicFile frame(frames / "frame_000003.ply");  // as --frames writes them
      particles.write(std::string(1 << 16, 'x'));
      frame.write("ply\n");
      ::raise(signal_number);
      _exit(0);  // not reached
    }
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == signal_number);
    CHECK(files_in(folder) == 0);
  }
}

TEST_CASE("without a signal, committed files stay and nothing else is left") {
  test::TempDir dir("nosignal");
  remove_temporary_files_on_signals();
  for (int i = 0; i < 40; ++i)  // more files than the handler's slots, one after the other
    write_file_atomically(dir.file("f" + std::to_string(i % 3)), [](AtomicFile& f) { f.write("ok"); });
  CHECK(files_in(dir.file("")) == 3);
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  signal(SIGHUP, SIG_DFL);
}

TEST_CASE("a signal ignored from the start (a background job's SIGINT) stays ignored") {
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    signal(SIGINT, SIG_IGN);
    remove_temporary_files_on_signals();
    ::raise(SIGINT);
    _exit(7);
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 7);
}
