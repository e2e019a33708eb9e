// Builds a scene from text and steps it through the installed library.
#include <loosehair/loosehair.hpp>

#include <cstdio>

int main() {
  const char* text = R"({"name": "consumer", "substeps": 10,
    "head": {"type": "sphere", "radius": 0.1},
    "hair": {"particles": 200, "length": 0.15, "mass": 0.02}})";
  loosehair::SceneDesc scene = loosehair::parseScene(text, "inline");
  loosehair::Solver solver = loosehair::buildSolver(scene);
  solver.advance(10);
  std::printf("stepped %llu steps, hash %016llx\n", static_cast<unsigned long long>(solver.stepCount()),
              static_cast<unsigned long long>(solver.stateHash()));
  return 0;
}
