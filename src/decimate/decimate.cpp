#include "sdmesh/decimate.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "decimate/collapser.hpp"
#include "decimate/mesh_state.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

using Clock = std::chrono::steady_clock;
using decimation::Collapser;
using decimation::MeshState;

// The mesh with its vertices renumbered along a Morton curve of their positions and its faces
// sorted by their lowest new vertex, so that neighbourhoods are close in memory during the
// collapses; input_vertex maps the new vertex indices back.
struct SpatialOrder {
    TriangleMesh mesh;
    std::vector<int> input_vertex;
};

SpatialOrder spatial_order(const TriangleMesh& mesh) {
    const int nv = mesh.num_vertices(), nf = mesh.num_faces();
    if (nv == 0) return {mesh, {}};  // no bounding box
    const Eigen::RowVector3d low = mesh.V.colwise().minCoeff();
    const double extent = std::max((mesh.V.colwise().maxCoeff() - low).maxCoeff(), std::numeric_limits<double>::min());
    std::vector<std::pair<unsigned long long, int>> code(static_cast<size_t>(nv));
    for (int v = 0; v < nv; ++v) {
        unsigned long long key = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const auto cell = static_cast<unsigned long long>((mesh.V(v, axis) - low[axis]) / extent * 2097151.0);
            for (int bit = 0; bit < 21; ++bit) key |= ((cell >> bit) & 1ULL) << (3 * bit + axis);
        }
        code[v] = {key, v};
    }
    std::sort(code.begin(), code.end());
    SpatialOrder out;
    out.input_vertex.resize(static_cast<size_t>(nv));
    std::vector<int> new_index(static_cast<size_t>(nv));
    out.mesh.V.resize(nv, 3);
    for (int i = 0; i < nv; ++i) {
        out.input_vertex[i] = code[i].second;
        new_index[code[i].second] = i;
        out.mesh.V.row(i) = mesh.V.row(code[i].second);
    }
    std::vector<std::pair<int, int>> face_order(static_cast<size_t>(nf));
    for (int f = 0; f < nf; ++f)
        face_order[f] = {std::min({new_index[mesh.F(f, 0)], new_index[mesh.F(f, 1)], new_index[mesh.F(f, 2)]}), f};
    std::sort(face_order.begin(), face_order.end());
    out.mesh.F.resize(nf, 3);
    for (int i = 0; i < nf; ++i)
        for (int k = 0; k < 3; ++k) out.mesh.F(i, k) = new_index[mesh.F(face_order[i].second, k)];
    return out;
}

// The last 1/kGlobalShare of the collapses before each stop follow one global order.
constexpr long long kGlobalShare = 64;

// Runs work(0) and work(1) side by side.
template <class Work>
void on_both_halves(const Work& work) {
    std::array<std::exception_ptr, 2> failure;
#pragma omp parallel for schedule(static, 1)
    for (int h = 0; h < 2; ++h) {
        try {
            work(h);
        } catch (...) {
            failure[h] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : failure)
        if (e) std::rethrow_exception(e);
}

// Queues every edge: with the half that owns both its ends, else with `whole`.
void queue_every_edge(const MeshState& mesh, bool halves, std::array<Collapser, 2>& half, Collapser& whole) {
    const int nv = static_cast<int>(mesh.P.size());
    if (!halves) {
        std::vector<int> ring;
        for (int u = 0; u < nv; ++u) {
            mesh.neighbours(u, ring);
            for (int w : ring)
                if (w > u) whole.push(u, w);
        }
        return;
    }
    std::array<std::vector<std::pair<int, int>>, 2> across;  // edges for `whole`, found by each half
    on_both_halves([&](int h) {
        std::vector<int> ring;
        for (int u = h == 0 ? 0 : mesh.split; u < (h == 0 ? mesh.split : nv); ++u) {
            mesh.neighbours(u, ring);
            for (int w : ring)
                if (w > u) {
                    if (mesh.owner[u] == h && mesh.owner[w] == h) half[h].push(u, w);
                    else across[h].emplace_back(u, w);
                }
        }
    });
    for (const auto& edges : across)
        for (const auto& [u, w] : edges) whole.push(u, w);
}

// Sets the three collapsers' clocks to the latest (see Collapser::clock) before one of them runs.
void sync_clocks(std::array<Collapser, 2>& half, Collapser& whole) {
    const long long clock = std::max({whole.clock(), half[0].clock(), half[1].clock()});
    whole.set_clock(clock);
    for (Collapser& c : half) c.set_clock(clock);
}

// Collapses in the two halves side by side until 1/kGlobalShare of the collapses before `stop`
// are left, then hands everything queued to `whole`. In steps: each takes a threshold from the
// keys queued, such that `reach` times the collapses left are keyed below it; each half
// collapses, in its own cheapest-first order, below the threshold and at most its share (by live
// vertices) of the collapses left; then `whole` does the same with the seam's collapses and those
// the halves handed over, so that the seam keeps up with the halves. Most keys are of candidates
// that a collapse makes stale or that are refused, so `reach` doubles while a step falls short of
// a quarter of the collapses left. Each half's steps depend only on the half and the seam's on the
// state the halves leave, so the result does not depend on the number of threads.
void collapse_in_halves(MeshState& mesh, std::array<Collapser, 2>& half, Collapser& whole, long long stop,
                        ProgressClock& progress) {
    const auto total_collapses = [&] { return whole.collapses() + half[0].collapses() + half[1].collapses(); };
    std::vector<double> keys;
    long long reach = 1;
    for (;;) {
        std::array<long long, 2> live_in{0, 0};
        for (int v = 0; v < static_cast<int>(mesh.alive.size()); ++v) live_in[mesh.half_of(v)] += mesh.alive[v];
        const long long live = live_in[0] + live_in[1];
        const long long left = live - stop - (live - stop) / kGlobalShare;
        keys.clear();
        for (const Collapser* c : {&half[0], &half[1], &whole}) c->append_keys(keys);
        if (left <= 0 || keys.empty()) break;
        const auto kth = keys.begin() + std::min(static_cast<long long>(keys.size()) - 1, reach * left);
        std::nth_element(keys.begin(), kth, keys.end());
        const double threshold = *kth;
        const long long before = total_collapses();
        sync_clocks(half, whole);
        // Half 0 speaks for both: one clock, never read on two threads at once.
        on_both_halves([&](int h) {
            half[h].collapse_below(threshold, left * live_in[h] / live, h == 0 ? &progress : nullptr);
        });
        for (Collapser& c : half) c.hand_over_to(whole);
        sync_clocks(half, whole);
        whole.collapse_below(threshold, left - (total_collapses() - before), &progress);
        const long long done = total_collapses() - before;
        if (done == 0) break;
        if (4 * done < left) reach *= 2;
    }
    for (Collapser& c : half) c.move_all_to(whole);
    sync_clocks(half, whole);
}

// Collapses to each level and then to the target (see collapse_in_halves with halves).
void collapse_to_stops(MeshState& mesh, const DecimateOptions& options, bool halves, long long target,
                       const std::vector<int>& input_vertex, DecimateResult& result) {
    Collapser whole(mesh, options, -1);
    std::array<Collapser, 2> half{Collapser(mesh, options, 0), Collapser(mesh, options, 1)};
    queue_every_edge(mesh, halves, half, whole);
    ProgressClock progress(options.progress);
    std::vector<long long> stops = options.levels;
    stops.push_back(target);
    for (size_t i = 0; i < stops.size(); ++i) {
        if (halves) collapse_in_halves(mesh, half, whole, stops[i], progress);
        if (!whole.collapse_count(mesh.live_vertices - stops[i], progress)) {
            result.report.status = DecimateStatus::stalled;
            break;
        }
        if (i + 1 == stops.size()) break;
        result.levels.push_back(mesh.result(input_vertex));
        if (halves)
            for (Collapser& c : half) whole.move_owned_to(c);
    }
    DecimateReport& report = result.report;
    for (const Collapser* c : {&whole, &half[0], &half[1]}) {
        report.collapses += c->collapses();
        report.rejected.topology += c->rejected().topology;
        report.rejected.not_delaunay += c->rejected().not_delaunay;
        report.rejected.normal_flip += c->rejected().normal_flip;
        report.rejected.max_error += c->rejected().max_error;
    }
}

void check_options(const DecimateOptions& o, long long input_vertices, long long target) {
    if (o.halves_from_vertices < 0) throw InvalidArgumentError("decimate: halves_from_vertices must be >= 0");
    if (o.target_vertices < 0) throw InvalidArgumentError("decimate: target_vertices must be >= 0");
    if (o.target_vertices == 0 && !(o.target_ratio > 0 && o.target_ratio <= 1))
        throw InvalidArgumentError("decimate: target_ratio must be in (0, 1]");
    if (!(o.max_error >= 0)) throw InvalidArgumentError("decimate: max_error must be >= 0");
    require_delaunay_tolerance(o.tolerance, "decimate");
    for (size_t i = 0; i < o.levels.size(); ++i)
        if (o.levels[i] <= target || o.levels[i] >= input_vertices || (i > 0 && o.levels[i] >= o.levels[i - 1]))
            throw InvalidArgumentError("decimate: level " + std::to_string(i) + " (" + std::to_string(o.levels[i]) +
                                       " vertices) must lie between the target (" + std::to_string(target) +
                                       ") and the input's " + std::to_string(input_vertices) +
                                       " vertices, in decreasing order");
}

}  // namespace

DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options) {
    const auto start = Clock::now();
    auto announce = [&](const std::string& phase) {
        if (options.progress) std::fprintf(stderr, "decimate: %s\n", phase.c_str());
    };
    announce("checking the input, " + std::to_string(mesh.num_vertices()) + " vertices and " +
             std::to_string(mesh.num_faces()) + " faces");
    require_indices_in_range(mesh);
    const double diagonal = require_supported_extent(mesh);
    const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
    const MeshInfo info = validate(mesh, edges, ValidateScope::defects);
    require_oriented_manifold(info, "decimate");
    const CertifyOptions certify_options{.boundary = options.boundary, .tolerance = options.tolerance};
    const long long input_vertices = info.vertices;
    const long long target = options.target_vertices > 0
                                 ? options.target_vertices
                                 : std::llround(options.target_ratio * static_cast<double>(input_vertices));
    check_options(options, input_vertices, target);
    const DelaunayCertificate input_certificate = certify(mesh, edges, certify_options);
    if (!input_certificate.self_delaunay)
        throw InvalidArgumentError(
            "decimate: the input is not self-Delaunay (" + std::to_string(input_certificate.non_delaunay_edges) +
            " non-Delaunay interior edges, " + std::to_string(input_certificate.boundary_obtuse_edges) +
            " obtuse boundary edges); convert it first (sdmesh convert, or sdmesh decimate --convert-first)");

    DecimateResult result;
    DecimateReport& report = result.report;
    report.input_vertices = input_vertices;
    report.input_faces = mesh.num_faces();
    report.target_vertices = target;
    announce("queueing the collapses of " + std::to_string(edges.num_edges()) + " edges");
    SpatialOrder ordered = spatial_order(mesh);
    // Collapses run at the scale of a unit diagonal, by a power of two (exact both ways; only far
    // from it): the quadrics hold fourth powers of lengths, which overflow from coordinates of
    // about 1e75 on. The spatial order permutes the vertices, so the diagonal is the input's.
    const int scale_exponent = far_unit_exponent(diagonal);
    if (scale_exponent != 0) ordered.mesh = scaled_by_power_of_two(ordered.mesh, -scale_exponent);
    // Two halves of the Morton order: two boxes of space.
    const bool halves = options.halves_from_vertices > 0 && input_vertices >= options.halves_from_vertices;
    const int nv = ordered.mesh.num_vertices();
    MeshState state(ordered.mesh, build_edge_table(ordered.mesh.F, nv), options, halves ? nv / 2 : nv, scale_exponent);
    collapse_to_stops(state, options, halves, target, ordered.input_vertex, result);
    result.mesh = state.result(ordered.input_vertex);
    report.output_vertices = result.mesh.num_vertices();
    report.output_faces = result.mesh.num_faces();
    announce("certifying the output");
    report.certificate = certify(result.mesh, certify_options);
    if (report.collapses > 0) {
        if (options.measure_hausdorff) announce("measuring the Hausdorff distance to the input");
        // A few samples per face of the input: the output's faces are larger, and sampled densely.
        const HausdorffOptions sampling{.samples_per_face = 4, .max_samples = 4'000'000, .mean = false};
        report.hausdorff_rel = options.measure_hausdorff ? hausdorff_distance(mesh, result.mesh, sampling).hausdorff_rel
                                                         : std::numeric_limits<double>::quiet_NaN();
    }
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

std::string_view to_string(DecimateStatus status) {
    return status == DecimateStatus::stalled ? "stalled" : "reached_target";
}

}  // namespace sdmesh
