// convert(): the checks, the Converter's loop and its edits of the mesh.
#include "sdmesh/convert.hpp"

#include "convert/converter.hpp"
#include "number_text.hpp"

namespace sdmesh::conversion {

void Converter::run(ConversionReport& report) {
    // Each edge's tests read only its hinge and, for its key, the flatness of its outer sides
    // (input_flat_ in a split conversion), so they run in parallel; the queue is filled in edge
    // order. keys: NaN for a locally Delaunay edge, else as for enqueue(). Reading a hinge waits
    // on memory (its faces and corners lie anywhere), so flatness and the verdict come from one
    // read, the hinges of later edges are requested ahead (faces, then corners), and the keys
    // follow once every flatness is known (skull: 0.39 -> 0.18 s).
    const int edges = mesh_.num_edges();
    std::vector<double> keys;
    detail::prefaulted_assign(keys, static_cast<size_t>(edges), 0.0);
    detail::prefaulted_assign(needs_point_, static_cast<size_t>(edges), char{0});
    constexpr double kDelaunay = std::numeric_limits<double>::quiet_NaN();
    constexpr int kAhead = detail::kPrefetchDistance;
#pragma omp parallel for schedule(static)
    for (int e = 0; e < edges; ++e) {
        if (e + 2 * kAhead < edges) mesh_.prefetch(mesh_.halfedge(e + 2 * kAhead));
        if (e + kAhead < edges) {
            const int h = mesh_.halfedge(e + kAhead);
            mesh_.prefetch(mesh_.twin(h));
            for (const int v : {mesh_.tail(h), mesh_.head(h), mesh_.opposite_vertex(h)}) __builtin_prefetch(&P_[v]);
        }
        const bool delaunay = is_delaunay(e);
        input_flat_[e] = dihedral_within(e, coplanar_angle_);
        keys[e] = delaunay ? kDelaunay : 0.0;
    }
#pragma omp parallel for schedule(dynamic, 4096)
    for (int e = 0; e < edges; ++e)
        if (!std::isnan(keys[e])) keys[e] = queue_key(e);
    for (int e = 0; e < edges; ++e) {
        if (std::isnan(keys[e])) continue;
        ++report.input_non_delaunay_edges;
        needs_point_[e] = !input_flat_[e];
        report.input_nonflat_non_delaunay_edges += needs_point_[e];
        enqueue(e, keys[e]);
    }
    if (options_.progress)
        std::fprintf(stderr, "convert: %lld of %d edges not locally Delaunay, %lld of them folds\n",
                     report.input_non_delaunay_edges, edges, report.input_nonflat_non_delaunay_edges);
    if (tracks_moves_) {
        input_plane_ = input_planes();
        home_.resize(static_cast<size_t>(mesh_.num_faces()));
        std::iota(home_.begin(), home_.end(), 0);
    }
    if (options_.method == ConvertMethod::split && options_.lower_bound)
        report.added_vertices_lower_bound = added_vertices_lower_bound();
    // Thin strips beside folds need points about as far apart as they are wide: of the 22 unseen
    // meshes that ran out of 10·|V| + 100,000, 14 of the 20 tried certify within this budget
    // (printers' beds, sofas: 190,000-990,000 vertices in 6-70 s).
    vertex_budget_ = options_.max_vertices > 0 ? options_.max_vertices : 10LL * input_vertices_ + 1000000;
    if (options_.method != ConvertMethod::flip) classify_input_vertices();
    if (options_.method != ConvertMethod::flip && options_.split_rule == SplitRule::interval) split_together(report);
    drain(report);
    if (options_.method == ConvertMethod::split && report.status == ConvertStatus::certified &&
        report.vertices_inside_faces == 0) {
        announce("removing the points no longer needed", report);
        remove_unneeded_points(report);
        announce("the fewest points per input edge", report);
        // What the edges' new points changed may let other points go; elsewhere none can.
        if (const std::vector<char> respaced = fewest_points_per_edge(report); !respaced.empty())
            remove_unneeded_points(report, &respaced);
        if (options_.local_search > 0) {
            // What the search changed may let other points go; elsewhere none can.
            const std::vector<char> changed = local_search(report);
            remove_unneeded_points(report, &changed);
        }
    }
}

std::vector<int> Converter::input_planes() const {
    const int input_faces = static_cast<int>(input_.F.rows());
    UnionFind planes(input_faces);
    for (int e = 0; e < input_edges_.num_edges(); ++e)
        if (const int g = input_face(e, 1); input_flat_[e] && g >= 0) planes.unite(input_face(e, 0), g);
    std::vector<int> plane_of(static_cast<size_t>(input_faces));
    for (int f = 0; f < input_faces; ++f) plane_of[f] = planes.find(f);
    return plane_of;
}

TriangleMesh Converter::result() const {
    // Input vertices keep their ids; points removed again leave no gap.
    std::vector<int> new_id(P_.size(), -1);
    int kept = 0;
    for (size_t v = 0; v < P_.size(); ++v)
        if (v < static_cast<size_t>(input_vertices_) || !removed_[v - input_vertices_]) new_id[v] = kept++;
    // Input vertices are copied: a coordinate far smaller than the diagonal is subnormal at the
    // unit scale, where it lost bits (1.234567e-170 next to 1e150 came back 1.2347855264902e-170).
    TriangleMesh out;
    out.V.resize(kept, 3);
    out.V.topRows(input_vertices_) = input_.V;
    for (size_t v = input_vertices_; v < P_.size(); ++v)
        if (new_id[v] >= 0)
            for (int i = 0; i < 3; ++i) out.V(new_id[v], i) = std::ldexp(P_[v][i], scale_exponent_);
    out.F = mesh_.faces();
    for (int f = 0; f < out.F.rows(); ++f)
        for (int k = 0; k < 3; ++k) out.F(f, k) = new_id[out.F(f, k)];
    return out;
}

SurfaceEdit Converter::surface_edit() const {
    SurfaceEdit edit;
    for (int f = 0; f < mesh_.num_faces(); ++f)  // in the order of HalfedgeMesh::faces()
        if (!mesh_.is_removed_face(f)) edit.changed_faces.push_back(moved_[f]);
    // The input faces that moved faces lay in, or all those of their plane; the input faces
    // under faces that spanned two planes are found by distance.
    edit.replaced_faces.assign(input_plane_.size(), 0);
    std::vector<char> replaced_plane(input_plane_.size(), 0);
    std::vector<const Replaced*> spanning;
    for (const Replaced& r : replaced_) {
        if (r.home >= 0)
            edit.replaced_faces[r.home] = 1;
        else if (r.home == kSpansPlanes)
            spanning.push_back(&r);
        else
            replaced_plane[plane_of_home(r.home)] = 1;
    }
    for (size_t f = 0; f < input_plane_.size(); ++f) edit.replaced_faces[f] |= replaced_plane[input_plane_[f]];
    edit.replaced.V.resize(3 * static_cast<Eigen::Index>(spanning.size()), 3);
    edit.replaced.F.resize(static_cast<Eigen::Index>(spanning.size()), 3);
    for (size_t t = 0; t < spanning.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Eigen::Index row = 3 * static_cast<Eigen::Index>(t) + k;
            const Eigen::Vector3d& p = P_[spanning[t]->corners[k]];
            for (int i = 0; i < 3; ++i) edit.replaced.V(row, i) = std::ldexp(p[i], scale_exponent_);
            edit.replaced.F(static_cast<Eigen::Index>(t), k) = static_cast<int>(row);
        }
    return edit;
}

void Converter::drain(ConversionReport& report, long long max_splits) {
    while (true) {
        // Edges that point removal took out since they were queued have no ends to measure.
        if (report.flips > detail::kFlipsPerEdgeBeforeLongestFirst * mesh_.num_edges())
            flat_queue_.longest_first([this](int f) { return mesh_.is_removed_edge(f) ? 0.0 : edge_length(f); });
        const int e = pop();
        if (e < 0) break;
        if (mesh_.is_removed_edge(e) || is_delaunay(e)) continue;
        if (heals_by_flip(e)) {
            if (report.flips >= flip_budget()) {
                report.status = ConvertStatus::budget_exhausted;
                break;
            }
            flip(e);
            ++report.flips;
        } else if (options_.method == ConvertMethod::flip) {
            continue;  // left for the final certificate to count
        } else if (mesh_.num_vertices() >= vertex_budget_) {
            report.status = ConvertStatus::budget_exhausted;
            break;
        } else if (report.splits >= max_splits) {
            break;
        } else {
            const long long splits_before = report.splits;  // more after it only if e was split
            split_across_strips(e, report, !trial_);
            if (input_edge_[e] < 0 && report.splits > splits_before) ++report.vertices_inside_faces;
        }
        if (!trial_ && progress_due())  // a trial's counts would be taken back
            std::fprintf(stderr, "convert: %lld splits, %lld flips, %zu queued, %d vertices\n", report.splits,
                         report.flips, flat_queue_.size() + physical_queue_.size(), mesh_.num_vertices());
    }
}

bool Converter::keep_one_spoke(int into, int x, int q, ConversionReport& report) {
    while (true) {
        const int h = side_into(into, x);
        std::vector<int> spokes;
        for (int out = HalfedgeMesh::next(h); mesh_.head(out) != q; out = HalfedgeMesh::next(mesh_.twin(out)))
            spokes.push_back(mesh_.edge(out));
        if (spokes.size() == 1) return true;
        const auto flippable = std::find_if(spokes.begin(), spokes.end(),
                                            [&](int s) { return is_flat(s, flat_angle_) && is_flippable(s); });
        if (flippable == spokes.end()) return false;
        flip(*flippable);
        ++report.flips;
    }
}

int Converter::undo_split(int x, ConversionReport& report) {
    auto [piece, other] = pieces_[x - input_vertices_];
    if (side_into(piece, x) < 0) std::swap(piece, other);  // on a boundary line
    const int p = other_end(piece, x), q = other_end(other, x);
    if (!keep_one_spoke(piece, x, q, report)) return -1;
    if (side_into(other, x) >= 0 && !keep_one_spoke(other, x, p, report)) return -1;
    const int h = side_into(piece, x), t = mesh_.twin(h);
    mesh_.merge(h);
    set_removed(x - input_vertices_, 1);
    repoint_piece(q, other, piece);
    for (const int side : {h, t}) {
        if (side < 0) continue;
        push(mesh_.edge(HalfedgeMesh::next(side)));
        push(mesh_.edge(HalfedgeMesh::prev(side)));
    }
    push(piece);
    return piece;
}

void Converter::flip(int e) {
    const Hinge k = hinge(e);
    const int outer[4] = {mesh_.edge(HalfedgeMesh::next(k.h)), mesh_.edge(HalfedgeMesh::prev(k.h)),
                          mesh_.edge(HalfedgeMesh::next(mesh_.twin(k.h))),
                          mesh_.edge(HalfedgeMesh::prev(mesh_.twin(k.h)))};
    const bool planar_quad = is_flat(e, coplanar_angle_);
    if (tracks_moves_) {  // the two new faces cover what the old ones did: moved if either was
        const int faces[2] = {HalfedgeMesh::face(k.h), HalfedgeMesh::face(mesh_.twin(k.h))};
        if (!planar_quad || moved_[faces[0]] || moved_[faces[1]])
            for (const int f : faces) set_moved(f);
        const int home = moved_[faces[0]] ? kSpansPlanes : merged_home(home_[faces[0]], home_[faces[1]]);
        for (const int f : faces) set_home(f, home);
    }
    mesh_.flip(e);
    set_input_edge(e, -1);  // the new diagonal crosses the input faces
    set_in_plane(e, static_cast<char>(planar_quad));
    for (int o : outer) {
        // A hybrid flip across a fold puts the outer sides next to faces of another plane.
        if (!planar_quad) set_in_plane(o, 0);
        push(o);
    }
}

bool Converter::keeps_angles(const Hinge& k, const Eigen::Vector3d& x) const {
    const double ax = distance(P_[k.a], x), bx = distance(P_[k.b], x);
    for (const int apex : {k.r, k.s}) {
        if (apex < 0) continue;
        const double apex_x = distance(P_[apex], x);
        if (!(triangle_area(ax, apex_x, dist(k.a, apex)) > 0 && triangle_area(bx, apex_x, dist(k.b, apex)) > 0))
            return false;
    }
    return true;
}

std::optional<Eigen::Vector3d> Converter::split_point(const Hinge& k, double l, double t) const {
    auto at = [&](double u) -> Eigen::Vector3d { return P_[k.a] + (std::clamp(u, 0.0, l) / l) * (P_[k.b] - P_[k.a]); };
    auto fits = [&](const Eigen::Vector3d& y) { return keeps_angles(k, y) && !on_a_vertex(k, y); };
    const Eigen::Vector3d x = at(t);
    if (fits(x)) return x;
    // An apex within rounding of the edge near one end (in spikes 1e9 times longer than wide)
    // leaves angles only to points about as close to that end.
    auto nearest_apex = [&](int end) { return k.s < 0 ? dist(end, k.r) : std::min(dist(end, k.r), dist(end, k.s)); };
    for (const double u : {0.5 * l, nearest_apex(k.a), l - nearest_apex(k.b)})
        if (const Eigen::Vector3d y = at(u); fits(y)) return y;
    // Without angles a face may still be mended by later splits (the spikes' faces are); a point
    // on a vertex never is.
    if (on_a_vertex(k, x)) return std::nullopt;
    return x;
}

bool Converter::within_rounding_of_an_end(const Hinge& k, const Eigen::Vector3d& x) const {
    constexpr double kWithinRounding = 0x1p-32;  // of the unit scale of P_
    return std::min(distance(P_[k.a], x), distance(P_[k.b], x)) < kWithinRounding;
}

bool Converter::on_a_vertex(const Hinge& k, const Eigen::Vector3d& x) const {
    for (const int v : {k.a, k.b, k.r, k.s})
        if (v >= 0 && P_[v] == x) return true;
    // Points 1e-15 from a fan's apex on different spokes had the same coordinates, two edges
    // apart: such points are looked up by position (a walk round the apex took minutes where
    // its fan held thousands of them).
    if (!within_rounding_of_an_end(k, x)) return false;
    const auto found = points_by_position_.find(position_key(x));
    if (found == points_by_position_.end()) return false;
    const int y = found->second;  // may be stale: taken back by a trial, or removed again
    return y < static_cast<int>(P_.size()) && P_[y] == x && !removed_[y - input_vertices_];
}

bool Converter::split(int e, std::optional<double> at) {
    const Hinge k = hinge(e);
    const double l = dist(k.a, k.b);
    // Cascades converging on a vertex reach pieces of 1e-15 of their edge, where points fell on
    // the vertex or within rounding of it: "certified" outputs had coincident vertices.
    const std::optional<Eigen::Vector3d> point = split_point(k, l, std::clamp(at ? *at : split_distance(k, l), 0.0, l));
    if (!point) return false;
    const Eigen::Vector3d& x = *point;
    const int first_new_edge = mesh_.num_edges();
    std::vector<int> outer = {mesh_.edge(HalfedgeMesh::next(k.h)), mesh_.edge(HalfedgeMesh::prev(k.h))};
    if (k.s >= 0) {
        const int twin = mesh_.twin(k.h);
        outer.push_back(mesh_.edge(HalfedgeMesh::next(twin)));
        outer.push_back(mesh_.edge(HalfedgeMesh::prev(twin)));
    }
    // The new faces are parts of the faces on e: the first of h's, the second of its twin's.
    const int split_faces[2] = {HalfedgeMesh::face(k.h), k.s >= 0 ? HalfedgeMesh::face(mesh_.twin(k.h)) : -1};
    const int first_new_face = mesh_.num_faces();
    mesh_.split(e);
    for (int f = first_new_face; f < mesh_.num_faces() && tracks_moves_; ++f) {
        moved_.push_back(moved_[split_faces[f - first_new_face]]);
        home_.push_back(home_[split_faces[f - first_new_face]]);
    }
    if (within_rounding_of_an_end(k, x)) points_by_position_[position_key(x)] = static_cast<int>(P_.size());
    P_.push_back(x);
    vertex_input_edge_.push_back(input_edge_[e]);
    removed_.push_back(0);
    // The other half lies on the same input edge as e; the spokes inside faces, so they are
    // flat whatever the rounding of x says (a spoke taken for a fold would be split, with
    // a vertex inside the face, and the next spokes are as noisy: far from the origin that
    // ran away to the vertex budget).
    input_edge_.push_back(input_edge_[e]);
    in_plane_.push_back(in_plane_[e]);
    while (static_cast<int>(input_edge_.size()) < mesh_.num_edges()) {
        input_edge_.push_back(-1);
        in_plane_.push_back(1);
    }
    queued_.resize(static_cast<size_t>(mesh_.num_edges()), 0);
    if (input_edge_[e] >= 0) {  // e keeps the half at a, the new edge the one at b
        pieces_.push_back({e, first_new_edge});
        repoint_piece(k.b, e, first_new_edge);
    } else {
        pieces_.push_back({-1, -1});
    }
    push(e);
    for (int n = first_new_edge; n < mesh_.num_edges(); ++n) push(n);
    for (int o : outer) push(o);
    return true;
}

}  // namespace sdmesh::conversion

namespace sdmesh {
namespace {

void check_options(const ConvertOptions& o) {
    require_delaunay_tolerance(o.tolerance, "convert");
    if (!(o.max_dihedral_deg >= 0 && o.max_dihedral_deg <= 180))
        throw InvalidArgumentError("convert: max_dihedral_deg must be in [0, 180], got " +
                                   detail::number_text(o.max_dihedral_deg));
    if (!(o.coplanar_tolerance >= 0 && o.coplanar_tolerance < std::numbers::pi / 2))
        throw InvalidArgumentError("convert: coplanar_tolerance must be in [0, π/2) radians, got " +
                                   detail::number_text(o.coplanar_tolerance));
    if (o.max_vertices < 0) throw InvalidArgumentError("convert: max_vertices must be >= 0");
    if (o.max_flips < 0) throw InvalidArgumentError("convert: max_flips must be >= 0");
    if (o.local_search < 0) throw InvalidArgumentError("convert: local_search must be >= 0");
    if (o.cascade_trials < 0) throw InvalidArgumentError("convert: cascade_trials must be >= 0");
}

}  // namespace

ConversionResult convert(const TriangleMesh& mesh, const ConvertOptions& options) {
    const auto start = conversion::Clock::now();
    check_options(options);
    if (options.progress)
        std::fprintf(stderr, "convert: checking the input, %d vertices and %d faces\n", mesh.num_vertices(),
                     mesh.num_faces());
    require_indices_in_range(mesh);
    const double diagonal = require_supported_extent(mesh);
    const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
    const MeshInfo info = validate(mesh, edges, ValidateScope::defects);
    require_oriented_manifold(info, "convert");

    ConversionResult result;
    ConversionReport& report = result.report;
    report.input_vertices = mesh.num_vertices();
    report.input_faces = mesh.num_faces();
    // Where flips across folds moved the surface: all the Hausdorff distance needs to sample.
    SurfaceEdit edit;
    {  // the converter's working memory is released before the output is certified
        conversion::Converter converter(mesh, edges, diagonal, options);
        converter.run(report);
        result.mesh = converter.result();
        if (options.measure_hausdorff && options.method != ConvertMethod::split) edit = converter.surface_edit();
    }
    report.output_vertices = result.mesh.num_vertices();
    report.output_faces = result.mesh.num_faces();
    if (options.progress) std::fprintf(stderr, "convert: certifying the output\n");
    report.certificate = certify(result.mesh, {.boundary = options.boundary, .tolerance = options.tolerance});
    if (report.status != ConvertStatus::budget_exhausted && !report.certificate.self_delaunay)
        report.status = ConvertStatus::not_certified;
    if (options.method == ConvertMethod::flip)
        report.unflippable_edges = report.certificate.non_delaunay_edges +
                                   (options.boundary == BoundaryPolicy::strict ? report.certificate.boundary_obtuse_edges : 0);
    // Split flips only inside planes, which at the default tolerance are exactly planar; above it,
    // its flips can move the surface anywhere in a plane, so the whole surface is sampled.
    const bool split_may_move = options.method == ConvertMethod::split && options.coplanar_tolerance > kExactlyCoplanar;
    if (report.flips > 0 && (options.method != ConvertMethod::split || split_may_move)) {
        if (options.progress && options.measure_hausdorff)
            std::fprintf(stderr, "convert: measuring the Hausdorff distance to the input\n");
        // A few samples per face: the flips change the surface by a fraction of an edge length.
        const HausdorffOptions sampling{.samples_per_face = 4, .max_samples = 4'000'000, .mean = false};
        report.hausdorff_rel =
            !options.measure_hausdorff ? std::numeric_limits<double>::quiet_NaN()
            : split_may_move           ? hausdorff_distance(mesh, result.mesh, sampling).hausdorff_rel
                                       : hausdorff_distance_of_edit(mesh, result.mesh, edit, sampling).hausdorff_rel;
    }
    report.seconds = std::chrono::duration<double>(conversion::Clock::now() - start).count();
    return result;
}

std::string_view to_string(ConvertStatus status) {
    switch (status) {
        case ConvertStatus::certified: return "certified";
        case ConvertStatus::budget_exhausted: return "budget_exhausted";
        case ConvertStatus::not_certified: return "not_certified";
    }
    return "unknown";
}

std::string_view to_string(ConvertMethod method) {
    switch (method) {
        case ConvertMethod::flip: return "flip";
        case ConvertMethod::split: return "split";
        case ConvertMethod::hybrid: return "hybrid";
    }
    return "unknown";
}

std::string_view to_string(SplitRule rule) {
    return rule == SplitRule::shell ? "shell" : "interval";
}

}  // namespace sdmesh
