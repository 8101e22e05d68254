// Conversion to a self-Delaunay mesh (issue: conversion front end), on the 1.6M-face skull by
// default; peak memory: run under /usr/bin/time -v.
//   bench_convert [--benchmark_filter=...]   mesh: $SDMESH_BENCH_MESH or oded_skull_midsub2.obj.gz

#include <string>

#include <benchmark/benchmark.h>

#include "benchmark_mesh.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/io.hpp"

namespace {

const sdmesh::TriangleMesh& mesh() { return sdmesh::bench::mesh("oded_skull_midsub2.obj.gz"); }

void run(benchmark::State& state, const sdmesh::ConvertOptions& options) {
    const sdmesh::TriangleMesh& input = mesh();  // read once, outside the timing
    sdmesh::ConversionReport report;
    for (auto _ : state) report = sdmesh::convert(input, options).report;
    state.counters["faces"] = static_cast<double>(report.input_faces);
    state.counters["input_non_delaunay"] = static_cast<double>(report.input_non_delaunay_edges);
    state.counters["added_vertices"] = static_cast<double>(report.output_vertices - report.input_vertices);
    state.counters["flips"] = static_cast<double>(report.flips);
    state.counters["certified"] = report.status == sdmesh::ConvertStatus::certified;
    if (options.local_search > 0) state.counters["local_search_saved"] = static_cast<double>(report.local_search_saved);
}

void BM_ConvertSplitInterval(benchmark::State& state) { run(state, {}); }
void BM_ConvertSplitShell(benchmark::State& state) { run(state, {.split_rule = sdmesh::SplitRule::shell}); }
// One pass of local search (opt-in); its cost is the excess over BM_ConvertSplitInterval.
void BM_ConvertSplitLocalSearch(benchmark::State& state) { run(state, {.local_search = 1}); }
void BM_ConvertHybrid10NoHausdorff(benchmark::State& state) {
    run(state, {.method = sdmesh::ConvertMethod::hybrid, .max_dihedral_deg = 10, .measure_hausdorff = false});
}

}  // namespace

BENCHMARK(BM_ConvertSplitInterval)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_ConvertSplitShell)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_ConvertSplitLocalSearch)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_ConvertHybrid10NoHausdorff)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
