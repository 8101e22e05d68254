// Delaunay-preserving decimation (issue #5): the igea mesh converted to self-Delaunay (split, not
// timed), then decimated to 10% of its vertices. Target: <= 15 s.
//   bench_decimate [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or igea_midsub1.obj.gz

#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/decimate.hpp"

namespace {

const sdmesh::TriangleMesh& converted() {
    static const sdmesh::TriangleMesh mesh = sdmesh::convert(sdmesh::bench::mesh("igea_midsub1.obj.gz")).mesh;
    return mesh;
}

void run(benchmark::State& state, sdmesh::DecimateOptions options) {
    const sdmesh::TriangleMesh& mesh = converted();  // converted once, outside the timing
    sdmesh::DecimateReport report;
    for (auto _ : state) report = sdmesh::decimate(mesh, options).report;
    state.counters["input_vertices"] = static_cast<double>(report.input_vertices);
    state.counters["output_vertices"] = static_cast<double>(report.output_vertices);
    state.counters["collapses"] = static_cast<double>(report.collapses);
    state.counters["rejected"] = static_cast<double>(report.rejected.topology + report.rejected.not_delaunay +
                                                     report.rejected.normal_flip + report.rejected.max_error);
    state.counters["reached_target"] = report.status == sdmesh::DecimateStatus::reached_target;
    state.counters["self_delaunay"] = report.certificate.self_delaunay;
    state.counters["hausdorff_rel"] = report.hausdorff_rel;
}

// The target: collapses, final certificate and Hausdorff measurement included.
void BM_Decimate10Percent(benchmark::State& state) { run(state, {.target_ratio = 0.1}); }
// Without the fallback candidates: only the quadric optimum inside the allowable region.
void BM_Decimate10PercentRegionOnly(benchmark::State& state) {
    run(state, {.target_ratio = 0.1, .search_candidates = false});
}

}  // namespace

BENCHMARK(BM_Decimate10Percent)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_Decimate10PercentRegionOnly)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
