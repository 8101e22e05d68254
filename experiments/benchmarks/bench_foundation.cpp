// Read, validate and certify the largest corpus mesh (issue: foundation).
//   bench_foundation [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or the 1.6M-face skull.

#include <string>

#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"

namespace {

constexpr const char* kMesh = "oded_skull_midsub2.obj.gz";

const sdmesh::TriangleMesh& mesh() { return sdmesh::bench::mesh(kMesh); }

void BM_Read(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::read_mesh(sdmesh::bench::mesh_path(kMesh)));
    state.counters["faces"] = mesh().num_faces();
}

void BM_EdgeTable(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::build_edge_table(mesh().F, mesh().num_vertices()));
}

void BM_Validate(benchmark::State& state) {
    const auto edges = sdmesh::build_edge_table(mesh().F, mesh().num_vertices());
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::validate(mesh(), edges));
}

void BM_Certificate(benchmark::State& state) {
    const auto edges = sdmesh::build_edge_table(mesh().F, mesh().num_vertices());
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::certify(mesh(), edges));
    state.counters["edges_per_second"] =
        benchmark::Counter(static_cast<double>(edges.num_edges()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_CheckEndToEnd(benchmark::State& state) {
    for (auto _ : state) {
        const auto m = sdmesh::read_mesh(sdmesh::bench::mesh_path(kMesh));
        const auto edges = sdmesh::build_edge_table(m.F, m.num_vertices());
        benchmark::DoNotOptimize(sdmesh::validate(m, edges));
        benchmark::DoNotOptimize(sdmesh::certify(m, edges));
    }
}

}  // namespace

BENCHMARK(BM_Read)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EdgeTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Validate)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Certificate)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CheckEndToEnd)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
