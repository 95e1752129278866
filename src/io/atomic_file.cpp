// Atomic file replacement: temporary file in the target's folder, fsync,
// rename. POSIX calls, because std::ofstream can neither create exclusively
// nor sync.
#include "pfill/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <csignal>
#include <cstring>
#include <system_error>

#include "pfill/error.hpp"

namespace fs = std::filesystem;

namespace pfill {
namespace {

std::atomic<unsigned> temporary_counter{0};

// Temporary files being written, for the signal handler to remove: fixed
// slots of plain chars, since a handler may neither allocate nor lock. A
// slot is claimed by a compare-and-swap on `state` (0 free, 1 filling,
// 2 live); the handler unlinks only live slots.
constexpr int kTemporarySlots = 32;
constexpr size_t kTemporaryPathBytes = 4096;
struct TemporarySlot {
  std::atomic<int> state{0};
  char path[kTemporaryPathBytes];
};
TemporarySlot temporary_slots[kTemporarySlots];

int register_temporary(const fs::path& path) {
  const std::string text = path.string();
  if (text.size() >= kTemporaryPathBytes) return -1;
  for (int i = 0; i < kTemporarySlots; ++i) {
    int expected = 0;
    if (!temporary_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(temporary_slots[i].path, text.c_str(), text.size() + 1);
    temporary_slots[i].state.store(2);
    return i;
  }
  return -1;  // more files open at once than slots: that one is not cleaned on a signal
}

void unregister_temporary(int slot) {
  if (slot >= 0) temporary_slots[slot].state.store(0);
}

// Where a first SIGINT or SIGTERM is only noted (defer_interrupts_to).
std::atomic<volatile std::sig_atomic_t*> deferred_interrupt{nullptr};

extern "C" void remove_temporaries_and_reraise(int signal_number) {
  volatile std::sig_atomic_t* noted = deferred_interrupt.load();
  if (noted && *noted == 0 && signal_number != SIGHUP) {
    *noted = signal_number;  // the work polls it and stops cleanly; a second signal ends the process
    return;
  }
  for (TemporarySlot& slot : temporary_slots)
    if (slot.state.load() == 2) ::unlink(slot.path);  // async-signal-safe
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);  // die of the signal, as the caller expects
}

fs::path folder_of(const fs::path& target) {
  const fs::path parent = target.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

}  // namespace

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  if (target_.filename().empty()) fail("the path names no file");
  {  // A symbolic link stays one: the file it points to is what gets replaced.
    std::error_code ec;
    if (fs::is_symlink(target_, ec)) {
      const fs::path resolved = fs::weakly_canonical(target_, ec);
      if (!ec && !resolved.filename().empty()) target_ = resolved;
    }
  }
  const fs::path folder = folder_of(target_);
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    fail("folder '" + folder.string() + "' does not exist (create it or choose another path)");
  if (fs::is_directory(target_, ec)) fail("it is a folder (give a file name)");

  // Hidden, unique name in the same folder, so the final rename stays on one
  // file system and is atomic.
  for (int attempt = 0; attempt < 100 && !file_; ++attempt) {
    temporary_ = folder / ("." + target_.filename().string() + ".tmp" +
                           std::to_string(::getpid()) + "-" +
                           std::to_string(temporary_counter.fetch_add(1)));
    // Listed before it exists, so that no signal can leave it behind.
    registry_slot_ = register_temporary(temporary_);
    const int fd = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      const int error = errno;
      unregister_temporary(registry_slot_);
      registry_slot_ = -1;
      errno = error;
      if (errno == EEXIST) continue;
      const std::string reason = std::strerror(errno);
      temporary_.clear();
      fail("cannot create a file in folder '" + folder.string() + "': " + reason +
           " (check its permissions or choose another path)");
    }
    file_ = ::fdopen(fd, "wb");
    if (!file_) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      fail(reason);
    }
  }
  if (!file_) fail("could not find a free temporary name in '" + folder.string() + "'");
  static constexpr size_t kBufferBytes = 1 << 20;
  std::setvbuf(file_, nullptr, _IOFBF, kBufferBytes);
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temporary_.empty()) {
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
  unregister_temporary(registry_slot_);
  registry_slot_ = -1;
}

void AtomicFile::fail(const std::string& reason) {
  discard();
  throw Error("cannot write '" + target_.string() + "': " + reason);
}

void AtomicFile::write(const void* data, size_t bytes) {
  if (!file_) fail("the file is already closed");
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes)
    fail(std::string(std::strerror(errno)) + " (disk full?)");
}

void AtomicFile::commit() {
  if (!file_) fail("the file is already closed");
  if (std::fflush(file_) != 0) fail(std::string(std::strerror(errno)) + " (disk full?)");
  if (::fsync(::fileno(file_)) != 0 && errno != EINVAL)
    fail(std::string("fsync failed: ") + std::strerror(errno));
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) fail(std::string(std::strerror(errno)));
  std::error_code ec;
  fs::rename(temporary_, target_, ec);
  if (ec) fail("cannot rename the temporary file into place: " + ec.message());
  committed_ = true;
  unregister_temporary(registry_slot_);
  registry_slot_ = -1;
}

void remove_temporary_files_on_signals() {
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_reraise;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // the handler itself restores the default before re-raising
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction before {};
    // A signal ignored from the start (a background job's SIGINT, nohup's
    // SIGHUP) stays ignored.
    if (::sigaction(signal_number, nullptr, &before) == 0 && before.sa_handler == SIG_IGN) continue;
    ::sigaction(signal_number, &action, nullptr);
  }
}

void defer_interrupts_to(volatile std::sig_atomic_t* flag) { deferred_interrupt.store(flag); }

void write_file_atomically(const fs::path& target, const std::function<void(AtomicFile&)>& fill) {
  AtomicFile file(target);
  fill(file);
  file.commit();
}

size_t remove_stale_temporaries(const fs::path& target) {
  const std::string prefix = "." + target.filename().string() + ".tmp";
  std::error_code ec;
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  size_t removed = 0;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    // PID-K after the prefix, digits only.
    const std::string rest = name.substr(prefix.size());
    const size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || rest.find_first_not_of("0123456789-") != std::string::npos) continue;
    const long pid = std::strtol(rest.substr(0, dash).c_str(), nullptr, 10);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    std::error_code remove_error;
    if (fs::remove(it->path(), remove_error)) ++removed;
  }
  return removed;
}

}  // namespace pfill
