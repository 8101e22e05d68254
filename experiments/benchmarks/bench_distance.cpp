// Closest-point tree and sampled Hausdorff distance on a 100k-face mesh against itself with one
// vertex moved (what a conversion or decimation report costs).
//   bench_distance [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or the koala.

#include <string>

#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/io.hpp"

namespace {

const sdmesh::TriangleMesh& mesh() { return sdmesh::bench::mesh("oded_koala.obj"); }

// The mesh with vertex 0 moved by 1% of its bounding-box diagonal.
const sdmesh::TriangleMesh& moved() {
    static const sdmesh::TriangleMesh copy = [] {
        sdmesh::TriangleMesh m = mesh();
        const double diagonal = sdmesh::bounding_box_diagonal(m);
        m.V(0, 2) += 0.01 * diagonal;
        return m;
    }();
    return copy;
}

void BM_TreeBuild(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(sdmesh::TriangleTree(mesh()));
    state.counters["faces"] = mesh().num_faces();
}

void BM_Hausdorff(benchmark::State& state) {
    sdmesh::HausdorffReport report;
    for (auto _ : state) report = sdmesh::hausdorff_distance(mesh(), moved());
    state.counters["samples"] = static_cast<double>(report.samples);
    state.counters["hausdorff_rel"] = report.hausdorff_rel;
    state.counters["samples_per_second"] =
        benchmark::Counter(static_cast<double>(report.samples), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_TreeBuild)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Hausdorff)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
