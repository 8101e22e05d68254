// Operator assembly on a large mesh (issue: operators): the Triangulation, then L and M with 1 and
// 2 threads, against a plain setFromTriplets assembly of the same L, in the same run.
//   bench_operators [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or igea_midsub1 (1.07M faces).
// Every iteration allocates its results afresh, so where first-touch page faults are slow (VMs)
// they can dominate; to time the arithmetic with memory the allocator keeps, run with
//   GLIBC_TUNABLES=glibc.malloc.mmap_threshold=4294967295:glibc.malloc.trim_threshold=4294967295

#include <omp.h>

#include <string>
#include <vector>

#include <Eigen/SparseCore>
#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"

namespace {

const sdmesh::TriangleMesh& mesh() { return sdmesh::bench::mesh("igea_midsub1.obj.gz"); }

const sdmesh::Triangulation& triangulation() {
    static const sdmesh::Triangulation t = sdmesh::Triangulation::from_mesh(mesh());
    return t;
}

// The textbook assembly: four triplets per halfedge, then setFromTriplets (sort and sum).
// Cotangents as in the library (one Kahan area per face), so that only the assembly differs.
Eigen::SparseMatrix<double> triplet_laplacian(const sdmesh::Triangulation& t) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(12 * static_cast<size_t>(t.num_faces()));
    for (int f = 0; f < t.num_faces(); ++f) {
        const double l[3] = {t.side(f, 0), t.side(f, 1), t.side(f, 2)};
        const double area = sdmesh::triangle_area(l[0], l[1], l[2]);
        for (int k = 0; k < 3; ++k) {
            const double w = sdmesh::cosine_numerator(l[k], l[(k + 1) % 3], l[(k + 2) % 3]) / (8 * area);
            const int i = t.F(f, (k + 1) % 3), j = t.F(f, (k + 2) % 3);
            triplets.emplace_back(i, j, -w);
            triplets.emplace_back(j, i, -w);
            triplets.emplace_back(i, i, w);
            triplets.emplace_back(j, j, w);
        }
    }
    Eigen::SparseMatrix<double> L(t.num_vertices, t.num_vertices);
    L.setFromTriplets(triplets.begin(), triplets.end());
    return L;
}

void set_counters(benchmark::State& state, const sdmesh::Triangulation& t) {
    state.counters["faces"] = t.num_faces();
    state.counters["threads"] = omp_get_max_threads();
}

void BM_Triangulation(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::Triangulation::from_mesh(mesh()));
    state.counters["faces"] = mesh().num_faces();
}

void BM_Laplacian(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation();  // built outside the timing
    omp_set_num_threads(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::cotan_laplacian(t));
    set_counters(state, t);
}

void BM_Mass(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation();  // built outside the timing
    omp_set_num_threads(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::mass_matrix(t));
    set_counters(state, t);
}

void BM_LaplacianAndMass(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation();  // built outside the timing
    omp_set_num_threads(static_cast<int>(state.range(0)));
    for (auto _ : state) {
        benchmark::DoNotOptimize(sdmesh::cotan_laplacian(t));
        benchmark::DoNotOptimize(sdmesh::mass_matrix(t));
    }
    set_counters(state, t);
}

void BM_TripletLaplacian(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation();  // built outside the timing
    for (auto _ : state) benchmark::DoNotOptimize(triplet_laplacian(t));
    state.counters["faces"] = t.num_faces();
}

}  // namespace

BENCHMARK(BM_Triangulation)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Laplacian)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Mass)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LaplacianAndMass)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TripletLaplacian)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
