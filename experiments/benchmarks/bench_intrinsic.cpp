// The intrinsic Delaunay triangulation of a large mesh (issue: intrinsic), single-threaded: the
// time of the whole call (input check, halfedge build, Lawson loop, output, proper count), the
// number of flips, and flips per second of the Lawson loop (flips_per_second) and of the call.
//   bench_intrinsic [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or oded_skull_midsub2.obj.gz

#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/intrinsic.hpp"

namespace {

const sdmesh::Triangulation& triangulation() {
    static const sdmesh::Triangulation t =
        sdmesh::Triangulation::from_mesh(sdmesh::bench::mesh("oded_skull_midsub2.obj.gz"));
    return t;
}

void BM_IntrinsicDelaunay(benchmark::State& state) {
    const sdmesh::Triangulation& t = triangulation();  // built outside the timing
    sdmesh::IntrinsicReport report;
    double flip_seconds = 0;
    for (auto _ : state) {
        sdmesh::IntrinsicResult result = sdmesh::intrinsic_delaunay(t);
        report = result.report;
        flip_seconds += report.flip_seconds;
        benchmark::DoNotOptimize(result);
    }
    const double flips = static_cast<double>(report.flips);
    flip_seconds /= static_cast<double>(state.iterations());
    state.counters["faces"] = t.num_faces();
    state.counters["flips"] = flips;
    state.counters["proper"] = report.proper;
    // The rate of the Lawson loop alone, and of the whole call.
    state.counters["flip_seconds"] = flip_seconds;
    state.counters["flips_per_second"] = flips / flip_seconds;
    state.counters["flips_per_call_second"] =
        benchmark::Counter(flips, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_IntrinsicDelaunay)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
