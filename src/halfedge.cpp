#include "halfedge.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "prefault.hpp"

namespace sdmesh {

HalfedgeMesh::HalfedgeMesh(const Triangulation& t)
    : HalfedgeMesh(t.F, t.face_edge, t.edge_halfedges, t.num_vertices) {}

HalfedgeMesh::HalfedgeMesh(const Eigen::MatrixX3i& F, const Eigen::MatrixX3i& face_edge,
                           const Eigen::MatrixX2i& edge_halfedges, int num_vertices, int spare_splits)
    : num_vertices_(num_vertices) {
    // Records written whole, in face order, into premapped pages; twins then scattered per edge.
    const auto num_faces = static_cast<size_t>(F.rows());
    const auto spare = static_cast<size_t>(spare_splits);  // each adds 2 faces and 3 edges
    face_.reserve(num_faces + 2 * spare);
    // Not on 2 MB pages, though flip loops read the records at random (2 % more flips/s on them):
    // on the VM measured their first mapping in a process took from 15 ms to 1.4 s per 128 MB,
    // and the skull's conversion 4.45–5.57 s against 4.48–4.59 s (experiments/README.md).
    detail::prefault(face_.data(), num_faces * sizeof(Face));
    for (int f = 0; f < F.rows(); ++f)
        face_.push_back({{0, 0, 0},
                         {F(f, 0), F(f, 1), F(f, 2)},
                         {-1, -1, -1},
                         {face_edge(f, 0), face_edge(f, 1), face_edge(f, 2)}});
    detail::prefaulted_assign(edge_halfedge_, static_cast<size_t>(edge_halfedges.rows()), 0,
                              static_cast<size_t>(edge_halfedges.rows()) + 3 * spare);
    for (int e = 0; e < edge_halfedges.rows(); ++e) {
        const int h0 = edge_halfedges(e, 0), h1 = edge_halfedges(e, 1);
        edge_halfedge_[e] = h0;
        if (h1 >= 0) twin_of(h0) = h1, twin_of(h1) = h0;
    }
}

void HalfedgeMesh::glue(int a, int b, int e) {
    if (a >= 0) twin_of(a) = b, edge_of(a) = e;
    if (b >= 0) twin_of(b) = a, edge_of(b) = e;
    halfedge_of(e) = a >= 0 ? a : b;
}

void HalfedgeMesh::move_side(int from, int to) {
    set_side_length(to, side_length(from));
    glue(to, twin(from), edge(from));
}

int HalfedgeMesh::add_face(int a, int b, int c) {
    face_.push_back({{0, 0, 0}, {a, b, c}, {-1, -1, -1}, {-1, -1, -1}});
    return num_faces() - 1;
}

int HalfedgeMesh::add_edge() {
    edge_halfedge_.push_back(-1);
    return num_edges() - 1;
}

void HalfedgeMesh::flip(int e) {
    const int h = edge_halfedge_[e], t = twin(h);
    const int f = face(h), g = face(t);
    const int r = opposite_vertex(h), p = tail(h), q = head(h), s = opposite_vertex(t);
    // The outer sides q->r, r->p (face f) and p->s, s->q (face g), and where they go: in (r, p, s)
    // slot 0 is p->s and slot 2 is r->p; in (s, q, r) slot 0 is q->r and slot 2 is s->q.
    const std::array<int, 4> from = {next(h), prev(h), next(t), prev(t)};
    const std::array<int, 4> to = {3 * g, 3 * f + 2, 3 * f, 3 * g + 2};
    std::array<int, 4> outer_twin{}, outer_edge{};
    std::array<double, 4> outer_length{};
    for (int i = 0; i < 4; ++i) {
        outer_twin[i] = twin(from[i]);
        outer_edge[i] = edge(from[i]);
        outer_length[i] = side_length(from[i]);
        // A Δ-complex may glue two outer sides of the pair to each other.
        const auto inside = std::find(from.begin(), from.end(), outer_twin[i]);
        if (inside != from.end()) outer_twin[i] = to[inside - from.begin()];
    }
    touch_face(f), touch_face(g);
    Face& face_f = face_[f];
    Face& face_g = face_[g];
    face_f.corner[0] = r, face_f.corner[1] = p, face_f.corner[2] = s;
    face_g.corner[0] = s, face_g.corner[1] = q, face_g.corner[2] = r;
    for (int i = 0; i < 4; ++i) {
        glue(to[i], outer_twin[i], outer_edge[i]);
        set_side_length(to[i], outer_length[i]);
    }
    glue(3 * f + 1, 3 * g + 1, e);  // s->r in f, r->s in g
}

int HalfedgeMesh::split(int e) {
    const int h = edge_halfedge_[e], t = twin(h);
    const int x = num_vertices_++;
    const int other_half = add_edge();

    // Face (r, p, q) of h becomes (r, p, x) in place plus the new face (r, x, q); the side q->r
    // moves to the new face, and the spoke joins x and r.
    const int f_new = add_face(opposite_vertex(h), x, head(h));
    const int spoke_h = add_edge();
    move_side(next(h), 3 * f_new + 1);
    corner_of(prev(h)) = x;
    glue(next(h), 3 * f_new + 2, spoke_h);
    if (t < 0) {
        glue(3 * f_new, -1, other_half);  // boundary half x->q
        return x;
    }
    // The twin's face (s, q, p) becomes (s, q, x) in place plus (s, x, p).
    const int g_new = add_face(opposite_vertex(t), x, head(t));
    const int spoke_t = add_edge();
    move_side(next(t), 3 * g_new + 1);
    corner_of(prev(t)) = x;
    glue(next(t), 3 * g_new + 2, spoke_t);
    glue(h, 3 * g_new, e);           // p->x and x->p
    glue(t, 3 * f_new, other_half);  // q->x and x->q
    return x;
}

void HalfedgeMesh::merge(int h) {
    const int e = edge(h), t = twin(h);
    // Face (r, p, x) of h takes the side q -> r of (r, x, q) and becomes (r, p, q).
    const int r_side = twin(next(h));  // r -> x
    const int removed_face_r = face(r_side), removed_spoke_r = edge(r_side), removed_half = edge(next(r_side));
    const int q = head(next(r_side));
    corner_of(prev(h)) = q;
    move_side(prev(r_side), next(h));
    corner_of(3 * removed_face_r) = -1;
    halfedge_of(removed_spoke_r) = -1;
    halfedge_of(removed_half) = -1;
    if (t >= 0) {
        // Face (s, x, p) of the twin takes the side s -> q of (s, q, x) and becomes (s, q, p).
        const int s_side = twin(prev(t));  // x -> s
        const int removed_face_s = face(s_side), removed_spoke_s = edge(s_side);
        corner_of(next(t)) = q;
        move_side(next(s_side), prev(t));
        corner_of(3 * removed_face_s) = -1;
        halfedge_of(removed_spoke_s) = -1;
    }
    glue(h, t, e);
}

namespace {

// The corners of the faces around the vertex of corner c, one per step: c, then one way round
// until the fan closes or meets the boundary, then, on a boundary, the other way from c. Across
// the side leaving a corner (prev) the next one is at slot prev(twin); across the side entering
// it (next), at slot next(twin).
class FanWalk {
public:
    FanWalk(const HalfedgeMesh& mesh, int c) : mesh_(mesh), start_(c), slot_(c) {}
    [[nodiscard]] int slot() const { return slot_; }  ///< -1 once the fan is done
    void advance() {
        if (!backward_) {
            if (const int across = mesh_.twin(HalfedgeMesh::prev(slot_)); across >= 0) {
                slot_ = HalfedgeMesh::prev(across);
                if (slot_ == start_) slot_ = -1;  // closed fan
                return;
            }
            backward_ = true;
            slot_ = start_;
        }
        const int across = mesh_.twin(HalfedgeMesh::next(slot_));
        slot_ = across < 0 ? -1 : HalfedgeMesh::next(across);
    }

private:
    const HalfedgeMesh& mesh_;
    int start_, slot_;
    bool backward_ = false;
};

}  // namespace

bool HalfedgeMesh::has_diagonal(int h) const {
    const int r = opposite_vertex(h), s = opposite_vertex(twin(h));
    // Either fan alone answers; in turns, the smaller one ends the walk (a fan's apex can have
    // tens of thousands of neighbours, and flips ask about it again and again).
    for (FanWalk at_r(*this, h), at_s(*this, twin(h)); at_r.slot() >= 0 && at_s.slot() >= 0;
         at_r.advance(), at_s.advance()) {
        if (tail(at_r.slot()) == s || head(at_r.slot()) == s) return true;
        if (tail(at_s.slot()) == r || head(at_s.slot()) == r) return true;
    }
    return false;
}

Triangulation HalfedgeMesh::to_triangulation(Eigen::VectorXd length) const {
    // One pass over the halfedges in order, each edge written by its first listed side: the
    // reads are sequential and only the edge writes scatter.
    Triangulation out;
    out.num_vertices = num_vertices_;
    const int nf = num_faces(), ne = num_edges();
    out.F.resize(nf, 3);
    out.E.resize(ne, 2);
    out.edge_halfedges.resize(ne, 2);
    out.face_edge.resize(nf, 3);
    out.face_edge_sign.resize(nf, 3);
    detail::prefault(out.F), detail::prefault(out.E), detail::prefault(out.edge_halfedges);
    detail::prefault(out.face_edge), detail::prefault(out.face_edge_sign);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * f + k, t = twin(h), e = edge(h), from = tail(h), to = head(h);
            const bool first = t < 0 || h < t;
            if (first) {
                out.E(e, 0) = std::min(from, to);
                out.E(e, 1) = std::max(from, to);
                out.edge_halfedges(e, 0) = h;
                out.edge_halfedges(e, 1) = t;
            }
            // E(e,0) is the smaller end. Both sides of a self-edge start there: the first listed
            // runs along it, its twin against it, so that d1 sees the two faces glued with
            // opposite orientations.
            const bool forward = from != to ? from < to : first;
            out.F(f, k) = corner(f, k);
            out.face_edge(f, k) = e;
            out.face_edge_sign(f, k) = static_cast<signed char>(forward ? 1 : -1);
        }
    out.length = std::move(length);
    return out;
}

Eigen::MatrixX3i HalfedgeMesh::faces() const {
    int kept = 0;
    for (int f = 0; f < num_faces(); ++f) kept += !is_removed_face(f);
    Eigen::MatrixX3i F(kept, 3);
    for (int f = 0, row = 0; f < num_faces(); ++f)
        if (!is_removed_face(f)) {
            for (int k = 0; k < 3; ++k) F(row, k) = corner(f, k);
            ++row;
        }
    return F;
}

void HalfedgeMesh::begin_trial() {
    in_trial_ = true;
    trial_faces_ = num_faces(), trial_edges_ = num_edges(), trial_vertices_ = num_vertices_;
    face_log_.clear(), edge_log_.clear();
}

void HalfedgeMesh::rollback() {
    for (auto it = face_log_.rbegin(); it != face_log_.rend(); ++it) face_[it->first] = it->second;
    for (auto it = edge_log_.rbegin(); it != edge_log_.rend(); ++it) edge_halfedge_[it->first] = it->second;
    face_.resize(static_cast<size_t>(trial_faces_));
    edge_halfedge_.resize(static_cast<size_t>(trial_edges_));
    num_vertices_ = trial_vertices_;
    commit();
}

void HalfedgeMesh::commit() {
    in_trial_ = false;
    face_log_.clear(), edge_log_.clear();
}

}  // namespace sdmesh
