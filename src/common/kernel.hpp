// What every kernel header shares: plain C++17, no Python. A kernel takes raw pointers, shapes
// and strides (in elements) and runs its loops with OpenMP; the thread count is the calling
// thread's OpenMP setting (OMP_NUM_THREADS, `bakeshop --threads`, bakeshop.threads.limit).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>

namespace bakeshop {

using index_t = std::ptrdiff_t;

// The first error raised inside a parallel loop, re-thrown after it (an exception must not
// leave an OpenMP region): `errors.fail("...")` in the loop, `errors.check()` after.
class Errors {
 public:
  void fail(const std::string& message) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failed_.exchange(true)) message_ = message;
  }
  bool failed() const { return failed_.load(std::memory_order_relaxed); }
  // Throws std::out_of_range (Python: IndexError) for a bad index, else std::invalid_argument
  // (ValueError) with the first message.
  void check() const {
    if (failed_) throw std::invalid_argument(message_);
  }

 private:
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::string message_;
};

}  // namespace bakeshop
