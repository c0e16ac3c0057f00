// memory_budget.h: the estimate's ordering and the refusals.
#include "pipeline/memory_budget.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace developable {
namespace {

// Sets DEVELOPABLE_MEMORY_BUDGET_MB for one test and restores it after.
class Budget {
 public:
  explicit Budget(const char* mib) {
    if (const char* old = std::getenv(kName)) saved_ = old, had_ = true;
    if (mib)
      setenv(kName, mib, 1);
    else
      unsetenv(kName);
  }
  ~Budget() {
    if (had_)
      setenv(kName, saved_.c_str(), 1);
    else
      unsetenv(kName);
  }

 private:
  static constexpr const char* kName = "DEVELOPABLE_MEMORY_BUDGET_MB";
  std::string saved_;
  bool had_ = false;
};

std::string refusal(int64_t vertices, int64_t triangles, const PipelineOptions& options) {
  try {
    check_memory_budget(vertices, triangles, options);
  } catch (const EngineError& e) {
    EXPECT_EQ(e.status(), Status::out_of_memory);
    return e.what();
  }
  return "";
}

TEST(MemoryBudget, EstimateGrowsWithTheMeshTheCoupledSolverAndThePolish) {
  PipelineOptions decoupled, coupled, paper;
  coupled.solver = Formulation::coupled;
  coupled.polish = 0;  // as in the paper mode, where the automatic polish is off
  decoupled.polish = 0;
  paper.mode = Mode::paper;
  double previous = 0.0;
  for (int64_t faces : {1000, 10000, 100000, 1000000}) {
    const double d = estimated_peak_bytes(faces / 2, faces, decoupled);
    EXPECT_GT(d, previous);
    previous = d;
    EXPECT_GT(estimated_peak_bytes(faces / 2, faces, coupled), d);
    // The same coupled factor; the refit mode adds the Anderson acceleration's
    // history, a few hundred bytes per vertex.
    const double refit_extra =
        estimated_peak_bytes(faces / 2, faces, coupled) - estimated_peak_bytes(faces / 2, faces, paper);
    EXPECT_GT(refit_extra, 0.0);
    EXPECT_LE(refit_extra, 400.0 * static_cast<double>(faces / 2));
    PipelineOptions polished;
    EXPECT_GT(estimated_peak_bytes(faces / 2, faces, polished), d);
  }
}

TEST(MemoryBudget, TheVariableSetsTheBudget) {
  Budget budget("64");
  EXPECT_EQ(memory_budget_bytes(), 64.0 * 1024 * 1024);
}

TEST(MemoryBudget, BadVariableFallsBackToPhysicalMemory) {
  Budget budget("not a number");
  EXPECT_GT(memory_budget_bytes(), 64.0 * 1024 * 1024);
}

TEST(MemoryBudget, RefusesOverTheBudgetAndSaysWhatToChange) {
  Budget budget("64");
  PipelineOptions options;
  EXPECT_EQ(refusal(1000, 2000, options), "");
  const std::string big = refusal(1000000, 2000000, options);
  EXPECT_NE(big.find("memory budget"), std::string::npos) << big;
  EXPECT_NE(big.find("decimate"), std::string::npos) << big;
  options.solver = Formulation::coupled;
  const std::string coupled = refusal(1000000, 2000000, options);
  EXPECT_NE(coupled.find("decoupled"), std::string::npos) << coupled;
}

TEST(MemoryBudget, CoupledIsRefusedSooner) {
  Budget budget("600");
  PipelineOptions decoupled, coupled;
  coupled.solver = Formulation::coupled;
  EXPECT_EQ(refusal(50000, 100000, decoupled), "");
  EXPECT_NE(refusal(50000, 100000, coupled), "");
}

}  // namespace
}  // namespace developable
