// Solvers on corpus meshes (issue: solvers): the k smallest eigenpairs of L φ = λ M φ (barycentric
// mass) on c3d_nefertiti (k = 50), oded_koala (k = 100) and igea_midsub1 (k = 50), the Cholesky
// solves they are made of, and heat-method geodesics on igea_midsub1 (precomputation, then one
// query). Operators are built outside the timed region. Compare with SciPy's eigsh on the same matrices: experiments/benchmarks/scipy_eigsh.py.
//   bench_eigen [--benchmark_filter=...] --benchmark_counters_tabular=true

#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <omp.h>

#include "sdmesh/cholesky.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"

namespace {

// Corpus meshes by file name, read once per process.
const sdmesh::Triangulation& triangulation(const std::string& file) {
    static std::map<std::string, sdmesh::Triangulation> cache;
    auto it = cache.find(file);
    if (it == cache.end())
        it = cache.emplace(file, sdmesh::Triangulation::from_mesh(
                                     sdmesh::read_mesh(std::string(SDMESH_CORPUS_DIR) + "/" + file)))
                 .first;
    return it->second;
}

void BM_Eigenpairs(benchmark::State& state, const std::string& file, int k, sdmesh::EigenSolver solver) {
    const sdmesh::Triangulation& t = triangulation(file);
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t), M = sdmesh::mass_matrix(t);
    sdmesh::EigenReport report;
    for (auto _ : state) {
        const sdmesh::EigenResult r = sdmesh::smallest_eigenpairs(L, M, {.k = k, .solver = solver});
        report = r.report;
        benchmark::DoNotOptimize(r.values.data());
    }
    state.counters["vertices"] = t.num_vertices;
    state.counters["k"] = k;
    state.counters["converged"] = report.status == sdmesh::EigenStatus::converged;
    state.counters["iterations"] = report.iterations;
    state.counters["solves"] = report.solves;
    state.counters["max_residual"] = report.max_residual;
}

// Block Lanczos (the default) and Spectra's Lanczos, alternately, so that both see the same machine.
constexpr auto kBlock = sdmesh::EigenSolver::block_lanczos;
constexpr auto kSpectra = sdmesh::EigenSolver::spectra_lanczos;
BENCHMARK_CAPTURE(BM_Eigenpairs, nefertiti_k50_block, "c3d_nefertiti.obj", 50, kBlock)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Eigenpairs, nefertiti_k50_spectra, "c3d_nefertiti.obj", 50, kSpectra)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Eigenpairs, koala_k100_block, "oded_koala.obj", 100, kBlock)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Eigenpairs, koala_k100_spectra, "oded_koala.obj", 100, kSpectra)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Eigenpairs, igea_k50_block, "igea_midsub1.obj.gz", 50, kBlock)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Eigenpairs, igea_k50_spectra, "igea_midsub1.obj.gz", 50, kSpectra)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

// Analysis + factorization of L − σM (as eigenpairs makes it) with each ordering.
void BM_CholeskyFactor(benchmark::State& state, const std::string& file, sdmesh::CholeskyOrdering ordering) {
    const sdmesh::Triangulation& t = triangulation(file);
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t), M = sdmesh::mass_matrix(t);
    const double sigma = -L.diagonal().sum() / (static_cast<double>(L.rows()) * M.diagonal().sum());
    const Eigen::SparseMatrix<double> A = L - sigma * M;
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::CholeskySolver(A, {.ordering = ordering}).rows());
    state.counters["vertices"] = t.num_vertices;
}
BENCHMARK_CAPTURE(BM_CholeskyFactor, igea_automatic, "igea_midsub1.obj.gz", sdmesh::CholeskyOrdering::automatic)
    ->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_CholeskyFactor, igea_amd, "igea_midsub1.obj.gz", sdmesh::CholeskyOrdering::amd)
    ->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_CholeskyFactor, igea_metis, "igea_midsub1.obj.gz", sdmesh::CholeskyOrdering::metis)
    ->Unit(benchmark::kMillisecond)->Iterations(2);

// One solve with the factor of L − σM (as eigenpairs uses it) for `columns` right-hand sides.
void BM_CholeskySolve(benchmark::State& state, const std::string& file) {
    const sdmesh::Triangulation& t = triangulation(file);
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t), M = sdmesh::mass_matrix(t);
    const double sigma = -L.diagonal().sum() / (static_cast<double>(L.rows()) * M.diagonal().sum());
    const sdmesh::CholeskySolver factor(Eigen::SparseMatrix<double>(L - sigma * M));
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(L.rows(), state.range(0));
    for (auto _ : state) benchmark::DoNotOptimize(factor.solve_columns(B).data());
    state.counters["vertices"] = t.num_vertices;
    state.counters["columns"] = static_cast<double>(state.range(0));
}
BENCHMARK_CAPTURE(BM_CholeskySolve, nefertiti, "c3d_nefertiti.obj")->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CholeskySolve, igea, "igea_midsub1.obj.gz")->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

// The argument is the OpenMP thread count: with two, the factorizations run side by side; with
// one, they must not run inside an OpenMP region (CHOLMOD was 6x slower there).
void BM_GeodesicPrecompute(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation("igea_midsub1.obj.gz");
    const int saved = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::HeatGeodesics(t).report().time);
    omp_set_num_threads(saved);
    state.counters["vertices"] = t.num_vertices;
}
// Process CPU time: the factorizations run on OpenMP threads that the default (main-thread) clock misses.
BENCHMARK(BM_GeodesicPrecompute)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(2)->MeasureProcessCPUTime()->UseRealTime();

void BM_GeodesicQuery(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation("igea_midsub1.obj.gz");
    const sdmesh::HeatGeodesics geodesics(t);
    int source = 0;
    for (auto _ : state) {
        const Eigen::VectorXd d = geodesics.distance({source});
        source = (source + 7919) % t.num_vertices;  // a different source each time
        benchmark::DoNotOptimize(d.data());
    }
    state.counters["vertices"] = t.num_vertices;
}
BENCHMARK(BM_GeodesicQuery)->Unit(benchmark::kMillisecond)->Iterations(5)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
