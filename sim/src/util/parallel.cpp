#include "util/parallel.hpp"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

namespace loosehair::parallel {
namespace {

std::atomic<std::int64_t> g_spin_ns{50'000};

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// A counter that threads wait on to change. bump() wakes the sleepers, and
// makes the system call only when there are any.
struct Signal {
  std::atomic<std::uint32_t> value{0};
  std::atomic<std::uint32_t> sleepers{0};

  void bump() {
    value.fetch_add(1, std::memory_order_seq_cst);
    if (sleepers.load(std::memory_order_seq_cst) != 0) value.notify_all();
  }
  // Returns once value != old: spins up to the spin time, then sleeps.
  void waitWhileEqual(std::uint32_t old) {
    if (value.load(std::memory_order_acquire) != old) return;
    const std::int64_t limit = g_spin_ns.load(std::memory_order_relaxed);
    if (limit > 0) {
      const auto t0 = std::chrono::steady_clock::now();
      for (;;) {
        for (int k = 0; k < 64; ++k) {
          if (value.load(std::memory_order_acquire) != old) return;
          cpuRelax();
        }
        if (std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count() > limit)
          break;
      }
    }
    // Sleepers are counted before the value is looked at again and bump()
    // changes the value before it counts them (both sequentially
    // consistent): either this thread sees the new value or bump() sees it
    // sleeping. The futex compares the value itself, so no wake is lost.
    sleepers.fetch_add(1, std::memory_order_seq_cst);
    while (value.load(std::memory_order_seq_cst) == old) value.wait(old, std::memory_order_seq_cst);
    sleepers.fetch_sub(1, std::memory_order_relaxed);
  }
};

class Team;
thread_local Team* tls_team = nullptr;  // the run this thread is in (null: alone)
thread_local int tls_index = 0;
thread_local int tls_depth = 0;  // runs this thread is inside (nested runs go serial)

// Sets the calling thread's run for a scope.
class InRun {
 public:
  InRun(Team* team, int index) : team_(tls_team), index_(tls_index) {
    tls_team = team;
    tls_index = index;
    ++tls_depth;
  }
  ~InRun() {
    --tls_depth;
    tls_team = team_;
    tls_index = index_;
  }
  InRun(const InRun&) = delete;
  InRun& operator=(const InRun&) = delete;

 private:
  Team* team_;
  int index_;
};

class Team {
 public:
  explicit Team(int size) : size_(size) {
    threads_.reserve(static_cast<std::size_t>(size - 1));
    for (int t = 1; t < size; ++t) threads_.emplace_back([this, t] { work(t); });
  }
  // Teams live until the process ends (the pool never frees one): their
  // threads wait asleep and end with the process.
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;

  int size() const { return size_; }

  void run(const Task& body) {
    task_ = &body;
    error_ = nullptr;
    start_.bump();  // publishes task_ (sequentially consistent)
    {
      InRun in(this, 0);
      execute();
    }
    if (error_) std::rethrow_exception(error_);
  }

  void barrier() {
    const std::uint32_t g = generation_.value.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == size_) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.bump();
    } else {
      generation_.waitWhileEqual(g);
    }
  }

 private:
  // The body, then the barrier that ends the run (no thread touches the
  // task after it, so run() may return).
  void execute() {
    try {
      (*task_)();
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    barrier();
  }

  void work(int index) {
    std::uint32_t seen = 0;
    for (;;) {
      start_.waitWhileEqual(seen);
      ++seen;  // one bump a run, and every thread takes part in every run
      InRun in(this, index);
      execute();
    }
  }

  const int size_;
  std::vector<std::thread> threads_;
  const Task* task_ = nullptr;
  Signal start_, generation_;
  std::atomic<int> arrived_{0};
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

// Idle teams, by size; a run takes one (or makes one) and gives it back.
struct Pool {
  std::mutex mutex;
  std::vector<Team*> idle;
};
Pool& pool() {
  static Pool* p = new Pool;  // never destroyed: teams may outlive static destruction
  return *p;
}

}  // namespace

void runTask(int threads, const Task& body) {
  if (threads <= 1 || tls_depth > 0) {
    InRun in(nullptr, 0);
    body();
    return;
  }
  Team* team = nullptr;
  {
    const std::lock_guard<std::mutex> lock(pool().mutex);
    auto& idle = pool().idle;
    for (std::size_t k = 0; k < idle.size(); ++k)
      if (idle[k]->size() == threads) {
        team = idle[k];
        idle.erase(idle.begin() + static_cast<std::ptrdiff_t>(k));
        break;
      }
  }
  if (!team) team = new Team(threads);
  struct GiveBack {
    Team* team;
    ~GiveBack() {
      const std::lock_guard<std::mutex> lock(pool().mutex);
      pool().idle.push_back(team);
    }
  } give_back{team};
  team->run(body);
}

int threadIndex() { return tls_team ? tls_index : 0; }
int threadCount() { return tls_team ? tls_team->size() : 1; }
void barrier() {
  if (tls_team) tls_team->barrier();
}

int availableThreads() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

void setSpinNanoseconds(std::int64_t ns) { g_spin_ns.store(ns < 0 ? 0 : ns, std::memory_order_relaxed); }
std::int64_t spinNanoseconds() { return g_spin_ns.load(std::memory_order_relaxed); }

}  // namespace loosehair::parallel
