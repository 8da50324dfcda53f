#pragma once
// Temporary files removed when the program is interrupted.
//
// Every writer in the tree writes to a temporary file next to its target and renames it into
// place (write_atomically.h), so a failure never leaves a partial file under the target's name. A signal that kills the
// program mid-write (Ctrl-C's SIGINT, SIGTERM, SIGHUP, or SIGXFSZ past a file-size limit) would
// still leave the partial temporary behind (found by scripts/bad-input-report: a 12 MB
// "sky.exr.tmp-…" after Ctrl-C). A writer therefore holds a TemporaryFileGuard on its temporary
// while writing it. The first guard installs a handler for those signals — only for signals
// still at their default action, so a program's own handling wins — that unlinks every guarded
// file, restores the default action and re-raises the signal: the program still dies of it, with
// the exit status shells expect. Async-signal-safe: fixed slots, lock-free atomics, unlink()
// and raise() only.

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstring>
#include <string>

namespace acdf {

namespace detail {

struct TemporaryFileSlot {
  std::atomic<int> state{0};  // kFree, kFilling, kGuarded
  char path[4096];
};
inline constexpr int kSlotFree = 0, kSlotFilling = 1, kSlotGuarded = 2;
// Files written at the same time, across threads; a writer beyond this many is not guarded.
inline constexpr std::size_t kTemporaryFileSlots = 32;
inline TemporaryFileSlot temporaryFileSlots[kTemporaryFileSlots];
inline constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGXFSZ};

inline void removeTemporaryFilesAndReraise(int signal) {
  for (TemporaryFileSlot& slot : temporaryFileSlots)
    if (slot.state.load() == kSlotGuarded) ::unlink(slot.path);
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

inline void installTemporaryFileCleanup() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = removeTemporaryFilesAndReraise;
    sigemptyset(&action.sa_mask);
    for (int s : kCleanupSignals) {
      struct sigaction current {};
      if (sigaction(s, nullptr, &current) == 0 && current.sa_handler == SIG_DFL) sigaction(s, &action, nullptr);
    }
    return true;
  }();
  (void)installed;
}

}  // namespace detail

// Guards `path` (a temporary file the caller has just created) until destruction: after the rename
// into place, or after the caller removed it on failure.
class TemporaryFileGuard {
 public:
  explicit TemporaryFileGuard(const std::string& path) {
    static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");
    detail::installTemporaryFileCleanup();
    if (path.size() >= sizeof(detail::TemporaryFileSlot::path)) return;
    for (detail::TemporaryFileSlot& slot : detail::temporaryFileSlots) {
      int expected = detail::kSlotFree;
      if (!slot.state.compare_exchange_strong(expected, detail::kSlotFilling)) continue;
      std::memcpy(slot.path, path.c_str(), path.size() + 1);
      slot.state.store(detail::kSlotGuarded);
      slot_ = &slot;
      return;
    }
  }
  ~TemporaryFileGuard() {
    if (slot_) slot_->state.store(detail::kSlotFree);
  }
  TemporaryFileGuard(const TemporaryFileGuard&) = delete;
  TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

 private:
  detail::TemporaryFileSlot* slot_ = nullptr;
};

}  // namespace acdf
