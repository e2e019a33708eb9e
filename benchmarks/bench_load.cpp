// Solver steps on an idle machine and on one whose every core is kept busy
// by another process, with 1 and 2 threads, side by side in one run:
//
//   build/release/benchmarks/loosehair_bench_load
//
// "load" is the number of competing processes (0, or one per core the
// process may use): each is a forked child spinning in a loop, started
// before the benchmark's first step and killed after its last. The figure
// that matters is real (wall) time a step; a thread count that is slower
// under load than one thread is a bug (docs/performance.md, "Threads on a
// busy machine"). The third argument is the waiting threads' spin time in
// microseconds before they sleep (parallel::setSpinNanoseconds; 50 is the
// default): runs with other values show why the default was chosen.
// threads:0 is the solver's own choice (the default of scenes and of the
// command line): all cores, or one while they are slower than one.
#include "loosehair/loosehair.hpp"
#include "util/parallel.hpp"

#include <benchmark/benchmark.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace loosehair;

struct Cached {
  std::unique_ptr<Solver> solver;
  Particles start;
};

// The scene after 20 steps, back at that state (and one untimed step on).
Solver& sceneAt(const std::string& name) {
  static std::map<std::string, Cached> cache;
  Cached& c = cache[name];
  if (!c.solver) {
    const SceneDesc scene = loadScene(LOOSEHAIR_SOURCE_DIR "/data/scenes/" + name + ".json");
    c.solver = std::make_unique<Solver>(buildSolver(scene));
    c.solver->advance(20);
    c.start = c.solver->particles();
  }
  c.solver->setKinematicState(c.start.position, c.start.velocity, c.start.direction);
  c.solver->step();  // absorbs the reset's corrections: not timed
  return *c.solver;
}

// Competing processes, each spinning on a core, for the life of the object.
class BusyProcesses {
 public:
  explicit BusyProcesses(int count) {
    for (int k = 0; k < count; ++k) {
      const pid_t pid = fork();
      if (pid == 0) {
        volatile unsigned long spin = 0;
        for (;;) spin = spin + 1;
      }
      if (pid > 0) pids_.push_back(pid);
    }
    if (count > 0) usleep(200'000);  // let the scheduler spread them
  }
  ~BusyProcesses() {
    for (pid_t pid : pids_) kill(pid, SIGKILL);
    for (pid_t pid : pids_) waitpid(pid, nullptr, 0);
  }
  BusyProcesses(const BusyProcesses&) = delete;
  BusyProcesses& operator=(const BusyProcesses&) = delete;

 private:
  std::vector<pid_t> pids_;
};

void BM_StepUnderLoad(benchmark::State& state, const std::string& scene) {
  const int threads = static_cast<int>(state.range(0));
  const bool loaded = state.range(1) != 0;
  const std::int64_t spin_before = parallel::spinNanoseconds();
  parallel::setSpinNanoseconds(state.range(2) * 1000);
  Solver& solver = sceneAt(scene);
  solver.setThreadCount(threads);
  const BusyProcesses busy(loaded ? parallel::availableThreads() : 0);
  for (auto _ : state) solver.step();
  parallel::setSpinNanoseconds(spin_before);
  state.counters["particles"] = static_cast<double>(solver.particles().size());
}

void arguments(benchmark::internal::Benchmark* b) {
  for (int load : {0, 1})
    for (int threads : {1, 2, 0}) b->Args({threads, load, 50});
  // the spin time's effect, two threads
  for (int load : {0, 1})
    for (int spin : {0, 10, 200}) b->Args({2, load, spin});
  b->ArgNames({"threads", "load", "spin_us"});
  b->Unit(benchmark::kMillisecond);
  b->UseRealTime();
}

// A fixed number of steps from the same state, so every configuration times
// the same steps (the hair falls and bunches: later steps cost more), and
// the automatic choice runs as it does in a real run, probes included.
BENCHMARK_CAPTURE(BM_StepUnderLoad, hang, std::string("hang"))->Apply(arguments)->Iterations(400);
BENCHMARK_CAPTURE(BM_StepUnderLoad, sphere_hang, std::string("sphere-hang"))->Apply(arguments)->Iterations(1000);

}  // namespace

BENCHMARK_MAIN();
