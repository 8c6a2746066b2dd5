// Internal: the renderer's threads. An Arena runs fork-join loops with a fixed number of worker
// slots; each loop body gets the slot it runs on (0 <= slot < threads()), so per-thread scratch
// needs no thread-local storage and no locks.
//
// Normally an Arena is a tbb::task_arena of its own (process-wide TBB settings are never touched).
// In ThreadSanitizer builds (FACET_STD_THREADS, set by the tsan preset) it runs loops on
// std::threads instead, with a static assignment of chunks to threads and a join at the end.
// Debian's libtbb is not built with -fsanitize=thread, so TSan cannot see the happens-before
// edges of TBB's scheduler and reports TBB's own task objects as races; with std::thread it sees
// every edge, and what it checks is what matters here: that facet's chunks never touch each
// other's data. Chunks of one loop share no synchronisation, so a race between them is reported.
#pragma once

#include <tbb/blocked_range.h>

#if defined(FACET_STD_THREADS)
#include <thread>
#include <type_traits>
#include <vector>
#else
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

#include <algorithm>

namespace facet::parallel {

// The threads an arena asked for `requested` can really run: TBB's process-wide limit on
// parallelism (max_allowed_parallelism: read here, never set; by default the machine's hardware
// threads) caps it. An arena asking for more workers than that limit makes libtbb print a warning
// to stderr, which a library must never cause, and would report threads that never ran.
inline int usable_threads(int requested) {
#if defined(FACET_STD_THREADS)
  return std::max(1, requested);
#else
  const std::size_t limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(std::clamp<std::size_t>(static_cast<std::size_t>(std::max(1, requested)), 1, std::max<std::size_t>(1, limit)));
#endif
}

class Arena {
 public:
  // `threads` is capped by usable_threads(); threads() tells what the arena really has.
  explicit Arena(int threads) : threads_(usable_threads(threads))
#if !defined(FACET_STD_THREADS)
                                ,
                                arena_(threads_)
#endif
  {
  }
  int threads() const { return threads_; }

  // Runs fn() with the arena's threads available to the loops it starts.
  template <class Fn>
  void execute(const Fn& fn) {
#if defined(FACET_STD_THREADS)
    fn();
#else
    arena_.execute(fn);
#endif
  }

  // body(sub_range, slot) for sub-ranges covering `range` (blocked_range: chunks of at least the
  // grain size). Inside execute() only.
  template <class Range, class Body>
  void parallel_for(const Range& range, const Body& body) {
#if defined(FACET_STD_THREADS)
    using Value = std::decay_t<decltype(range.begin())>;  // int or std::size_t ranges
    const auto grain = static_cast<Value>(range.grainsize());
    std::vector<Range> chunks;
    for (Value b = range.begin(); b < range.end();) {
      const Value e = range.end() - b > grain ? b + grain : range.end();
      chunks.emplace_back(b, e, range.grainsize());
      b = e;
    }
    auto run = [&](int slot) {
      for (std::size_t c = static_cast<std::size_t>(slot); c < chunks.size(); c += static_cast<std::size_t>(threads_)) {
        body(chunks[c], slot);
      }
    };
    std::vector<std::thread> helpers;
    for (int slot = 1; slot < threads_; ++slot) helpers.emplace_back(run, slot);
    run(0);
    for (auto& t : helpers) t.join();
#else
    tbb::parallel_for(range, [&](const Range& sub) { body(sub, tbb::this_task_arena::current_thread_index()); });
#endif
  }

 private:
  int threads_;
#if !defined(FACET_STD_THREADS)
  tbb::task_arena arena_;
#endif
};

}  // namespace facet::parallel
