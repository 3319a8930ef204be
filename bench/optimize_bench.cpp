// The optimization methods' own cost per generation (ask + tell, the fitness a trivial sum), in
// 10 and 50 dimensions, with each method's default population: what a run spends besides
// its evaluations (docs/optimization.md, docs/performance.md). Google Benchmark.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "gaitlab/optimize/method.h"

using namespace gaitlab::optimize;

namespace {
std::vector<Parameter> box(int n) {
    std::vector<Parameter> p;
    for (int i = 0; i < n; ++i)
        p.push_back({"x" + std::to_string(i), -5, 5, false});
    return p;
}

void generation(benchmark::State& state, std::unique_ptr<Method> m) {
    std::int64_t individuals = 0;
    for (auto _ : state) {
        const auto& xs = m->ask();
        std::vector<double> f;
        f.reserve(xs.size());
        for (const auto& x : xs) {
            double s = 0;
            for (double v : x)
                s -= (v - 1) * (v - 1);
            f.push_back(s);
        }
        individuals += static_cast<std::int64_t>(xs.size());
        m->tell(f);
    }
    state.counters["individuals"] = benchmark::Counter(static_cast<double>(individuals) /
                                                       static_cast<double>(state.iterations()));
}

void ga(benchmark::State& s) {
    generation(s, make_ga(box(static_cast<int>(s.range(0))), {}, 1));
}
void cmaes(benchmark::State& s) {
    generation(s, make_cmaes(box(static_cast<int>(s.range(0))), {}, 1));
}
void cmaes_lambda50(benchmark::State& s) {
    CmaesOptions o;
    o.population = 50;
    generation(s, make_cmaes(box(static_cast<int>(s.range(0))), o, 1));
}
void pgpe(benchmark::State& s) {
    generation(s, make_pgpe(box(static_cast<int>(s.range(0))), {}, 1));
}
void save(benchmark::State& s) {
    auto m = make_cmaes(box(static_cast<int>(s.range(0))), {}, 1);
    for (auto _ : s)
        benchmark::DoNotOptimize(m->save());
}
}  // namespace

BENCHMARK(ga)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);
BENCHMARK(cmaes)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);
BENCHMARK(cmaes_lambda50)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);
BENCHMARK(pgpe)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);
BENCHMARK(save)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
