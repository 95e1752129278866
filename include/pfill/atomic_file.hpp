/// @file atomic_file.hpp
/// @brief Writing a file so that readers see either the old file or the
/// complete new one, never a partial one: the bytes go to a temporary name in
/// the same folder, are flushed to disk, and only then renamed over the
/// target. Every pfill writer (particles, PNG) goes through this.
#pragma once
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

namespace pfill {

class AtomicFile {
 public:
  /// Creates the temporary file beside `target`; throws pfill::Error naming
  /// the target and the reason (folder missing, not writable, target is a
  /// folder).
  explicit AtomicFile(std::filesystem::path target);
  /// Removes the temporary file unless commit() succeeded; never throws.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends bytes; throws pfill::Error when the disk refuses them.
  void write(const void* data, size_t bytes);
  void write(const std::string& text) { write(text.data(), text.size()); }

  /// Flushes, syncs, closes and renames the temporary file over the target.
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  [[noreturn]] void fail(const std::string& reason);
  void discard() noexcept;

  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  int registry_slot_ = -1;  ///< its entry in the list a signal handler cleans up
};

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every
/// temporary file an AtomicFile is writing at that moment (async-signal-safe:
/// unlink only), then let the signal end the process as it would have.
/// A signal that was ignored when it is called stays ignored. Programs call
/// it once at start; a library must not.
void remove_temporary_files_on_signals();

/// While `flag` is set (not null), a first SIGINT or SIGTERM only stores its
/// number in *flag, for long work to poll and stop cleanly (the fill's
/// FillOptions::cancelled); a second one removes the temporary files and ends
/// the process as above. nullptr restores the plain behaviour.
void defer_interrupts_to(volatile std::sig_atomic_t* flag);

/// Removes the temporary files of earlier writes of `target` whose process
/// is gone (a SIGKILL during the final rename cannot be caught: it left
/// `.NAME.tmpPID-K` behind); returns how many. Others' live writes are kept.
size_t remove_stale_temporaries(const std::filesystem::path& target);

/// Opens an AtomicFile for `target`, lets `fill` write into it and commits;
/// if `fill` throws, the temporary file is removed, any existing target is
/// left as it was, and the exception propagates.
void write_file_atomically(const std::filesystem::path& target,
                           const std::function<void(AtomicFile&)>& fill);

}  // namespace pfill
