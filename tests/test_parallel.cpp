// The solver's threads (sim/src/util/parallel.hpp, thread_choice.hpp): teams run
// every index once, barriers order the phases, nested runs and exceptions
// are safe, concurrent callers get teams of their own; the automatic thread
// count goes to one thread when one is faster and stays on all when they
// are, with rare probes; and it never changes a result.
#include "util/parallel.hpp"
#include "test_support.hpp"
#include "util/thread_choice.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace loosehair;

TEST(Parallel, EveryThreadRunsOnceWithItsIndex) {
  for (int threads : {1, 2, 3, 5}) {
    std::vector<std::atomic<int>> seen(static_cast<std::size_t>(threads));
    std::atomic<int> wrong_count{0};
    parallel::run(threads, [&] {
      seen[static_cast<std::size_t>(parallel::threadIndex())] += 1;
      if (parallel::threadCount() != threads) ++wrong_count;
    });
    for (auto& s : seen) EXPECT_EQ(s.load(), 1) << threads << " threads";
    EXPECT_EQ(wrong_count.load(), 0);
  }
  EXPECT_EQ(parallel::threadIndex(), 0);
  EXPECT_EQ(parallel::threadCount(), 1);
}

TEST(Parallel, SharesCoverEveryItemOnce) {
  for (std::size_t n : {0u, 1u, 2u, 7u, 1000u}) {
    std::vector<int> hits(n, 0);
    parallel::forEach(3, n, [&](std::size_t i) { ++hits[i]; });  // each i by one thread
    for (int h : hits) EXPECT_EQ(h, 1);
  }
}

TEST(Parallel, BarrierSeparatesPhases) {
  constexpr int kThreads = 3, kRounds = 200;
  std::vector<int> slot(kThreads, 0);
  std::atomic<int> violations{0};
  parallel::run(kThreads, [&] {
    const int me = parallel::threadIndex();
    for (int round = 1; round <= kRounds; ++round) {
      slot[static_cast<std::size_t>(me)] = round;
      parallel::barrier();
      for (int other = 0; other < kThreads; ++other)
        if (slot[static_cast<std::size_t>(other)] != round) ++violations;
      parallel::barrier();
    }
  });
  EXPECT_EQ(violations.load(), 0);
}

TEST(Parallel, NestedRunsGoSerialAndExceptionsReachTheCaller) {
  std::atomic<int> inner_runs{0};
  parallel::run(2, [&] {
    parallel::run(2, [&] {
      EXPECT_EQ(parallel::threadCount(), 1);
      ++inner_runs;
    });
    EXPECT_EQ(parallel::threadCount(), 2);  // the outer team is back
  });
  EXPECT_EQ(inner_runs.load(), 2);
  EXPECT_THROW(parallel::run(2,
                             [] {
                               if (parallel::threadIndex() == 1) throw std::runtime_error("worker");
                             }),
               std::runtime_error);
  // the team is still usable
  std::atomic<int> after{0};
  parallel::run(2, [&] { ++after; });
  EXPECT_EQ(after.load(), 2);
}

TEST(Parallel, ConcurrentCallersEachGetATeam) {
  std::atomic<long> total{0};
  auto caller = [&] {
    for (int k = 0; k < 200; ++k)
      parallel::run(2, [&] {
        parallel::barrier();
        ++total;
      });
  };
  std::thread a(caller), b(caller);
  a.join();
  b.join();
  EXPECT_EQ(total.load(), 2 * 200 * 2);
}

TEST(Parallel, WaitersThatSleepAreWoken) {
  const auto spin = parallel::spinNanoseconds();
  parallel::setSpinNanoseconds(0);  // every wait sleeps on the futex
  std::atomic<int> count{0};
  for (int k = 0; k < 100; ++k)
    parallel::run(2, [&] {
      parallel::barrier();
      ++count;
    });
  parallel::setSpinNanoseconds(spin);
  EXPECT_EQ(count.load(), 200);
}

namespace {

// Steps of a machine where `many` threads take `t_many` seconds and one
// thread `t_one`; returns the share of steps that ran on one thread.
double shareOnOne(ThreadChoice& choice, double t_many, double t_one, int steps) {
  int one = 0;
  for (int k = 0; k < steps; ++k) {
    const bool single = choice.next() == 1;
    one += single ? 1 : 0;
    choice.record(single ? t_one : t_many);
  }
  return static_cast<double>(one) / steps;
}

}  // namespace

TEST(ThreadChoice, StaysOnAllThreadsWhileTheyAreFaster) {
  ThreadChoice choice(2);
  EXPECT_EQ(choice.next(), 2);
  // an idle machine: two threads 1.7x faster; the probes of one thread are
  // a small share of the steps, and rarer the longer it runs
  const double early = shareOnOne(choice, 1.0e-3, 1.7e-3, 500);
  const double late = shareOnOne(choice, 1.0e-3, 1.7e-3, 5000);
  EXPECT_LT(early, 0.05);
  EXPECT_LT(late, 0.005);
  EXPECT_EQ(choice.next(), 2);
}

TEST(ThreadChoice, GoesToOneThreadOnABusyMachineAndBackWhenItIsIdle) {
  ThreadChoice choice(2);
  (void)shareOnOne(choice, 1.0e-3, 1.7e-3, 300);
  // other processes take every core: two threads 3x slower than one
  const double busy = shareOnOne(choice, 9.0e-3, 3.0e-3, 2000);
  EXPECT_GT(busy, 0.97);
  EXPECT_EQ(choice.next(), 1);
  // the load goes: two threads are faster again, and are found within a
  // few hundred steps
  const double idle = shareOnOne(choice, 1.0e-3, 1.7e-3, 2000);
  EXPECT_LT(idle, 0.25);
  EXPECT_EQ(shareOnOne(choice, 1.0e-3, 1.7e-3, 1), 0.0);
}

TEST(ThreadChoice, OneThreadAvailableMeansOne) {
  ThreadChoice choice(1);
  for (int k = 0; k < 100; ++k) {
    EXPECT_EQ(choice.next(), 1);
    choice.record(1e-3);
  }
}

TEST(Determinism, TheSolversOwnThreadCountGivesTheSameBits) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/tests/data/tiny.json");
  scene.sim.threads = 1;
  Solver one = buildSolver(scene);
  scene.sim.threads = 0;  // the default: the solver chooses, step by step
  Solver automatic = buildSolver(scene);
  for (int k = 0; k < 200; ++k) {
    one.step();
    automatic.step();
  }
  EXPECT_EQ(one.stateHash(), automatic.stateHash());
  EXPECT_EQ(automatic.threadCount(), parallel::availableThreads());
}

// A thread count out of range from the library (the command line allows
// 1-1024) is refused with the other solver parameters, naming the field;
// the set-up, whose strands are grown on several threads, must not try to
// start that many first.
TEST(Parallel, ASceneAskingForTooManyThreadsIsRefusedByName) {
  SceneDesc scene = loadScene(lhtest::sourceDir() + "/tests/data/tiny.json");
  for (int threads : {parallel::kMaxThreads + 1, 1000000, -3}) {
    scene.sim.threads = threads;
    try {
      (void)buildSolver(scene);
      ADD_FAILURE() << threads << " threads were accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("solver.threads"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(std::to_string(threads)), std::string::npos) << e.what();
      // and no advice about the time step, which is not what is wrong
      EXPECT_EQ(std::string(e.what()).find("time_step"), std::string::npos) << e.what();
    }
  }
}
