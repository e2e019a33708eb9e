// Threads of the solver: persistent teams that wait without starving a busy
// machine (docs/design.md, "Threads").
//
// parallel::run(T, body) runs body() on T threads, the caller being thread
// 0, and returns when all have finished; inside, threadIndex() and
// threadCount() say which thread this is, barrier() waits for the whole
// team, share(n) is the calling thread's contiguous part of n items. A team's
// threads stay alive between runs (one team per concurrent caller, kept in a
// process-wide pool) and wait for the next run, or at a barrier, by spinning
// for a bounded time and then sleeping on a futex, so a thread that the
// kernel has descheduled costs the others little more than that bound,
// where OpenMP's default (about 3 ms of spinning at every barrier in
// libgomp) made a step 40-100x slower on a loaded machine. The policy is
// the program's own: no environment variable changes it.
//
// Results never depend on the thread count: every pass written for a team
// gives each item the same arithmetic whichever thread does it, and the
// reductions are of integers (order-free) or of exact min/max.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <utility>

namespace loosehair::parallel {

/// A function to run, by reference (the caller keeps it alive).
class Task {
 public:
  template <class F>
  explicit Task(F& f) : object_(&f), call_([](void* o) { (*static_cast<F*>(o))(); }) {}
  void operator()() const { call_(object_); }

 private:
  void* object_;
  void (*call_)(void*);
};

/// Runs `body` on `threads` threads (the caller is thread 0). With one
/// thread, or from inside another run, body runs on the caller alone (a team
/// of one). An exception thrown by any thread is rethrown here, after all
/// have returned; a body that throws must not have a barrier left to meet.
void runTask(int threads, const Task& body);
template <class F>
void run(int threads, F&& body) {
  runTask(threads, Task(body));
}

/// The calling thread's index in the current run (0 outside any run).
int threadIndex();
/// The number of threads of the current run (1 outside any run).
int threadCount();
/// Waits until every thread of the current run has reached it.
void barrier();

/// The calling thread's part [begin, end) of n items: contiguous, in
/// thread order, the sizes differing by at most one.
inline std::pair<std::size_t, std::size_t> share(std::size_t n) {
  const auto t = static_cast<std::size_t>(threadIndex()), c = static_cast<std::size_t>(threadCount());
  return {n * t / c, n * (t + 1) / c};
}

/// for i in [0, n): f(i), the items shared as share() does.
template <class F>
void forEach(int threads, std::size_t n, F&& f) {
  run(threads, [&] {
    const auto [b, e] = share(n);
    for (std::size_t i = b; i < e; ++i) f(i);
  });
}

/// f(i) for i in [0, n), the items handed out one at a time to whichever
/// thread is free: for items of uneven cost whose results do not depend on
/// which thread ran them (the order of the bits stays the caller's).
template <class F>
void forEachDynamic(int threads, std::size_t n, F&& f) {
  std::atomic<std::size_t> next{0};
  run(threads, [&] {
    for (std::size_t i = next.fetch_add(1, std::memory_order_relaxed); i < n;
         i = next.fetch_add(1, std::memory_order_relaxed))
      f(i);
  });
}

/// The number of hardware threads this process may use (its CPU affinity).
int availableThreads();

/// The most worker threads a scene or the solver may ask for.
inline constexpr int kMaxThreads = 1024;

/// How long a waiting thread spins before it sleeps, in nanoseconds
/// (default 50 us: longer than the solver's usual waits at a barrier on an
/// idle machine, far shorter than the time slice a descheduled thread is
/// away for). Set it only for measurements; 0 sleeps at once.
void setSpinNanoseconds(std::int64_t ns);
std::int64_t spinNanoseconds();

}  // namespace loosehair::parallel
