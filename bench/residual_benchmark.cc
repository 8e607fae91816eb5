// nrsfm_residual_benchmark: Google Benchmark micro-benchmarks of the
// reprojection residual per K (tests/problems/reprojection_error_oracle.h,
// problems/ reprojection_cost_function.h): one Evaluate() of one observation,
// residuals only and residuals + all Jacobians, for
//   Hand/K         ReprojectionCostFunction<K> (what the library uses)
//   HandDynamic/K  ReprojectionCostFunction<Eigen::Dynamic> (K > 16 fallback)
//   AutoDiff/K     ReprojectionError<K> (compile-time K, reference)
//   DynAutoDiff/K  DynamicReprojectionError (run-time K)
// Run: ./build/bench/nrsfm_residual_benchmark [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <ceres/cost_function.h>

#include <memory>
#include <random>
#include <vector>

#include "problems/reprojection_cost_function.h"
#include "tests/problems/reprojection_error_oracle.h"

namespace nrsfm {
namespace {

// Parameters and Jacobian storage of one observation with K bases.
struct Block {
  explicit Block(int k)
      : rotation{0.1, -0.2, 0.3},
        translation{0.5, -0.5},
        weights(k),
        basis(3 * k),
        residuals(2),
        jacobian_storage{std::vector<double>(6), std::vector<double>(4),
                         std::vector<double>(2 * k),
                         std::vector<double>(6 * k)} {
    std::mt19937_64 engine(1);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (double& w : weights) w = uniform(engine);
    for (double& b : basis) b = uniform(engine);
    parameters = {rotation, translation, weights.data(), basis.data()};
    for (auto& j : jacobian_storage) jacobians.push_back(j.data());
  }
  double rotation[3];
  double translation[2];
  std::vector<double> weights, basis, residuals;
  std::vector<std::vector<double>> jacobian_storage;
  std::vector<const double*> parameters;
  std::vector<double*> jacobians;
};

void Run(benchmark::State& state, const ceres::CostFunction& cost, int k,
         bool with_jacobians) {
  Block block(k);
  for (auto _ : state) {
    const bool ok =
        cost.Evaluate(block.parameters.data(), block.residuals.data(),
                      with_jacobians ? block.jacobians.data() : nullptr);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(block.residuals.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}

const Eigen::Vector2d kObservation(0.3, -0.7);

template <int K>
void BM_Hand(benchmark::State& state) {
  ReprojectionCostFunction<K> cost(K, false, kObservation, 1.0);
  Run(state, cost, K, state.range(0) != 0);
}

void BM_HandDynamic(benchmark::State& state) {
  const int k = static_cast<int>(state.range(1));
  ReprojectionCostFunction<Eigen::Dynamic> cost(k, false, kObservation, 1.0);
  Run(state, cost, k, state.range(0) != 0);
}

template <int K>
void BM_AutoDiff(benchmark::State& state) {
  std::unique_ptr<ceres::CostFunction> cost(
      ReprojectionError<K>::Create(kObservation, 1.0));
  Run(state, *cost, K, state.range(0) != 0);
}

void BM_DynAutoDiff(benchmark::State& state) {
  const int k = static_cast<int>(state.range(1));
  std::unique_ptr<ceres::CostFunction> cost(
      DynamicReprojectionError::Create(k, false, kObservation, 1.0));
  Run(state, *cost, k, state.range(0) != 0);
}

// Arg 0: 0 = residuals only, 1 = residuals + Jacobians.
#define NRSFM_PER_K(K)                                            \
  BENCHMARK_TEMPLATE(BM_Hand, K)->ArgName("jac")->Arg(0)->Arg(1); \
  BENCHMARK_TEMPLATE(BM_AutoDiff, K)->ArgName("jac")->Arg(0)->Arg(1);
NRSFM_PER_K(1)
NRSFM_PER_K(2)
NRSFM_PER_K(4)
NRSFM_PER_K(8)
NRSFM_PER_K(12)
NRSFM_PER_K(16)
#undef NRSFM_PER_K

BENCHMARK(BM_HandDynamic)
    ->ArgNames({"jac", "K"})
    ->ArgsProduct({{0, 1}, {1, 2, 4, 8, 12, 16, 24}});
BENCHMARK(BM_DynAutoDiff)
    ->ArgNames({"jac", "K"})
    ->ArgsProduct({{0, 1}, {1, 2, 4, 8, 12, 16, 24}});

}  // namespace
}  // namespace nrsfm

BENCHMARK_MAIN();
