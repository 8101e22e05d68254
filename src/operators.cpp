#include "sdmesh/operators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "prefault.hpp"

// Determinism: parallel loops compute one value per face, edge or column, each from data fixed by
// the triangulation; sums over several elements run serially in face or edge order, or within
// one column in row order. So results are bit-identical for any number of threads.

namespace sdmesh {
namespace {

// Below this many iterations a loop runs on one thread: starting a team costs more.
constexpr int kMinParallel = 4096;

void require_sizes(const Triangulation& t) {
    const int nf = t.num_faces(), ne = t.num_edges();
    if (t.num_vertices < 0 || t.face_edge.rows() != nf || t.face_edge_sign.rows() != nf ||
        t.edge_halfedges.rows() != ne || t.length.size() != ne)
        throw InvalidMeshError("operators: triangulation arrays do not match " + std::to_string(nf) + " faces and " +
                               std::to_string(ne) + " edges");
}

bool is_loop(const Triangulation& t, int e) { return t.E(e, 0) == t.E(e, 1); }

// Cotangent of corner k of face f, whose area is given.
double cotangent(const Triangulation& t, int f, int k, double area) {
    return cosine_numerator(t.side(f, k), t.side(f, (k + 1) % 3), t.side(f, (k + 2) % 3)) / (4.0 * area);
}

// Per vertex: Σ value(f, k) over the corners k of faces f at the vertex, in face order.
template <class CornerValue>
Eigen::VectorXd sum_at_corners(const Triangulation& t, CornerValue value) {
    auto sum = detail::prefaulted_constant<Eigen::VectorXd>(t.num_vertices, 1, 0.0);
    for (int f = 0; f < t.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) sum[t.F(f, k)] += value(f, k);
    return sum;
}

// A symmetric |V| x |V| matrix with the pattern of L: entry (i,j), i ≠ j, is the sum of
// offdiag(e) over the non-loop edges e joining i and j, in edge order; entry (v,v) is
// diagonal(v, s), s the sum of the off-diagonal entries of column v in row order.
template <class EdgeValue, class Diagonal>
Eigen::SparseMatrix<double> vertex_matrix(const Triangulation& t, EdgeValue offdiag, Diagonal diagonal) {
    const int nv = t.num_vertices, ne = t.num_edges();
    Eigen::SparseMatrix<double> m(nv, nv);
    int* outer = m.outerIndexPtr();
    for (int v = 0; v < nv; ++v) outer[v + 1] = 1;
    for (int e = 0; e < ne; ++e)
        if (!is_loop(t, e)) {
            ++outer[t.E(e, 0) + 1];
            ++outer[t.E(e, 1) + 1];
        }
    for (int v = 0; v < nv; ++v) outer[v + 1] += outer[v];
    m.resizeNonZeros(outer[nv]);
    int* inner = m.innerIndexPtr();
    double* value = m.valuePtr();
    detail::prefault(inner, sizeof(int) * static_cast<size_t>(outer[nv]));
    detail::prefault(value, sizeof(double) * static_cast<size_t>(outer[nv]));
    // Diagonal first, then the edges in edge order.
    const std::unique_ptr<int[]> cursor(new int[nv]);
    for (int v = 0; v < nv; ++v) {
        inner[outer[v]] = v;
        value[outer[v]] = 0;
        cursor[v] = outer[v] + 1;
    }
    for (int e = 0; e < ne; ++e) {
        if (is_loop(t, e)) continue;
        const int a = t.E(e, 0), b = t.E(e, 1);
        const double x = offdiag(e);
        inner[cursor[a]] = b;
        value[cursor[a]++] = x;
        inner[cursor[b]] = a;
        value[cursor[b]++] = x;
    }
    // Per column: stable insertion sort by row (linear on the sorted edges of from_mesh), then
    // parallel edges are added up and the diagonal is set.
    int merged = 0;
    const std::unique_ptr<int[]> count(new int[nv]);
#pragma omp parallel for schedule(static) reduction(+ : merged) if (nv >= kMinParallel)
    for (int v = 0; v < nv; ++v) {
        const int begin = outer[v], end = outer[v + 1];
        for (int i = begin + 1; i < end; ++i) {
            const int row = inner[i];
            const double x = value[i];
            int j = i;
            for (; j > begin && inner[j - 1] > row; --j) {
                inner[j] = inner[j - 1];
                value[j] = value[j - 1];
            }
            inner[j] = row;
            value[j] = x;
        }
        int n = begin + 1;
        for (int i = begin + 1; i < end; ++i) {
            if (inner[i] == inner[n - 1]) {
                value[n - 1] += value[i];
            } else {
                inner[n] = inner[i];
                value[n++] = value[i];
            }
        }
        double sum = 0;
        int d = begin;
        for (int i = begin; i < n; ++i) {
            if (inner[i] == v) d = i;
            else sum += value[i];
        }
        value[d] = diagonal(v, sum);
        count[v] = n - begin;
        merged += n != end;
    }
    if (merged > 0) {  // parallel edges (Δ-complexes only): close the gaps
        m.uncompress();
        std::copy(count.get(), count.get() + nv, m.innerNonZeroPtr());
        m.makeCompressed();
    }
    return m;
}

// Triplets summed into a column-major matrix; zero sums (of integer entries) are dropped.
Eigen::SparseMatrix<double> from_integer_triplets(int rows, int cols, const std::vector<Eigen::Triplet<double>>& triplets) {
    Eigen::SparseMatrix<double> m(rows, cols);
    m.setFromTriplets(triplets.begin(), triplets.end());
    m.prune([](Eigen::Index, Eigen::Index, double x) { return x != 0.0; });
    return m;
}

}  // namespace

Eigen::SparseMatrix<double> d0(const Triangulation& t) {
    require_sizes(t);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(2 * static_cast<size_t>(t.num_edges()));
    for (int e = 0; e < t.num_edges(); ++e) {
        triplets.emplace_back(e, t.E(e, 0), -1.0);
        triplets.emplace_back(e, t.E(e, 1), 1.0);
    }
    return from_integer_triplets(t.num_edges(), t.num_vertices, triplets);
}

Eigen::SparseMatrix<double> d1(const Triangulation& t) {
    require_sizes(t);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(3 * static_cast<size_t>(t.num_faces()));
    for (int f = 0; f < t.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) triplets.emplace_back(f, t.face_edge(f, k), t.face_edge_sign(f, k));
    return from_integer_triplets(t.num_faces(), t.num_edges(), triplets);
}

Eigen::VectorXd face_areas(const Triangulation& t) {
    require_sizes(t);
    const int nf = t.num_faces();
    Eigen::VectorXd area(nf);
    detail::prefault(area);
#pragma omp parallel for schedule(static) if (nf >= kMinParallel)
    for (int f = 0; f < nf; ++f) {
        detail::prefetch_sides_ahead(t, f);
        area[f] = triangle_area(t.side(f, 0), t.side(f, 1), t.side(f, 2));
    }
    return area;
}

Eigen::VectorXd star0(const Triangulation& t) {
    // Edge by edge (not corner by corner), so that non-negative weights give a non-negative sum.
    const Eigen::VectorXd w = star1(t);
    auto area = detail::prefaulted_constant<Eigen::VectorXd>(t.num_vertices, 1, 0.0);
    for (int e = 0; e < t.num_edges(); ++e) {
        const double term = t.length[e] * t.length[e] * w[e] / 4;
        area[t.E(e, 0)] += term;
        area[t.E(e, 1)] += term;
    }
    return area;
}

Eigen::VectorXd star1(const Triangulation& t) {
    require_sizes(t);
    // Cotangents face by face (each face's lengths read once), then paired up edge by edge.
    const int nf = t.num_faces(), ne = t.num_edges();
    const std::unique_ptr<double[]> cot(new double[3 * static_cast<size_t>(nf)]);
    detail::prefault(cot.get(), sizeof(double) * 3 * static_cast<size_t>(nf));
#pragma omp parallel for schedule(static) if (nf >= kMinParallel)
    for (int f = 0; f < nf; ++f) {
        detail::prefetch_sides_ahead(t, f);
        const double area = triangle_area(t.side(f, 0), t.side(f, 1), t.side(f, 2));
        for (int k = 0; k < 3; ++k) cot[3 * f + k] = cotangent(t, f, k, area);
    }
    Eigen::VectorXd w(ne);
    detail::prefault(w);
#pragma omp parallel for schedule(static) if (ne >= kMinParallel)
    for (int e = 0; e < ne; ++e) {
        if (e + detail::kPrefetchDistance < ne)  // the corners of an edge are random reads too
            for (const int h : t.edge_halfedges.row(e + detail::kPrefetchDistance))
                if (h >= 0) __builtin_prefetch(&cot[h]);
        const int h1 = t.edge_halfedges(e, 1);
        w[e] = (cot[t.edge_halfedges(e, 0)] + (h1 >= 0 ? cot[h1] : 0.0)) / 2;
    }
    return w;
}

Eigen::VectorXd star2(const Triangulation& t) { return face_areas(t).cwiseInverse(); }

Eigen::VectorXd inverse_star(const Eigen::VectorXd& star, std::string_view name) {
    Eigen::Index first = -1, bad = 0;
    for (Eigen::Index i = 0; i < star.size(); ++i)
        if (!(star[i] > 0) || !std::isfinite(star[i])) {
            if (first < 0) first = i;
            ++bad;
        }
    if (first >= 0) {
        char value[32];
        std::snprintf(value, sizeof value, "%.6g", star[first]);
        throw NumericalError("cannot invert " + std::string(name) + ": entry " + std::to_string(first) + " is " +
                             value + " (" + std::to_string(bad) + " of " + std::to_string(star.size()) +
                             " entries are not positive and finite)");
    }
    return star.cwiseInverse();
}

Eigen::SparseMatrix<double> diagonal_matrix(const Eigen::VectorXd& diagonal) {
    const int n = static_cast<int>(diagonal.size());
    Eigen::SparseMatrix<double> m(n, n);
    m.resizeNonZeros(n);
    detail::prefault(m.innerIndexPtr(), sizeof(int) * static_cast<size_t>(n));
    detail::prefault(m.valuePtr(), sizeof(double) * static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        m.outerIndexPtr()[i + 1] = i + 1;
        m.innerIndexPtr()[i] = i;
        m.valuePtr()[i] = diagonal[i];
    }
    return m;
}

Eigen::SparseMatrix<double> cotan_laplacian(const Triangulation& t) {
    const Eigen::VectorXd w = star1(t);
    return vertex_matrix(
        t, [&](int e) { return -w[e]; }, [](int, double offdiag_sum) { return -offdiag_sum; });
}

Eigen::SparseMatrix<double> mass_matrix(const Triangulation& t, MassType type) {
    const Eigen::VectorXd area = face_areas(t);
    switch (type) {
        case MassType::barycentric:
            return diagonal_matrix(sum_at_corners(t, [&](int f, int) { return area[f] / 3; }));
        case MassType::circumcentric: return diagonal_matrix(star0(t));
        case MassType::mixed_voronoi:
            // Meyer et al. 2003: Voronoi areas in a non-obtuse face, else area/2 to the obtuse
            // corner and area/4 to the others.
            return diagonal_matrix(sum_at_corners(t, [&](int f, int k) {
                const double cot[3] = {cotangent(t, f, 0, area[f]), cotangent(t, f, 1, area[f]),
                                       cotangent(t, f, 2, area[f])};
                if (cot[0] < 0 || cot[1] < 0 || cot[2] < 0) return cot[k] < 0 ? area[f] / 2 : area[f] / 4;
                const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                return (t.side(f, k1) * t.side(f, k1) * cot[k1] + t.side(f, k2) * t.side(f, k2) * cot[k2]) / 8;
            }));
        case MassType::galerkin: {
            // Per face, area/6 for each corner and area/12 for each ordered pair of corners; a
            // pair at the same vertex (a self-loop's ends) lands on the diagonal.
            const Eigen::VectorXd diagonal = sum_at_corners(t, [&](int f, int k) {
                const int v = t.F(f, k);
                return area[f] / 6 + area[f] / 12 * ((t.F(f, (k + 1) % 3) == v) + (t.F(f, (k + 2) % 3) == v));
            });
            return vertex_matrix(
                t,
                [&](int e) {
                    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
                    return (area[h0 / 3] + (h1 >= 0 ? area[h1 / 3] : 0.0)) / 12;
                },
                [&](int v, double) { return diagonal[v]; });
        }
    }
    throw InvalidArgumentError("mass_matrix: unknown mass type " + std::to_string(static_cast<int>(type)));
}

Eigen::VectorXd angle_defects(const Triangulation& t) {
    require_sizes(t);
    const int nf = t.num_faces();
    const std::unique_ptr<double[]> angle(new double[3 * static_cast<size_t>(nf)]);
#pragma omp parallel for schedule(static) if (nf >= kMinParallel)
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k)
            angle[3 * f + k] = corner_angle(t.side(f, k), t.side(f, (k + 1) % 3), t.side(f, (k + 2) % 3));
    const Eigen::VectorXd angle_sum = sum_at_corners(t, [&](int f, int k) { return angle[3 * f + k]; });
    std::vector<bool> boundary(t.num_vertices, false);
    for (int e = 0; e < t.num_edges(); ++e)
        if (t.is_boundary(e)) boundary[t.E(e, 0)] = boundary[t.E(e, 1)] = true;
    Eigen::VectorXd defect(t.num_vertices);
    for (int v = 0; v < t.num_vertices; ++v)
        defect[v] = (boundary[v] ? std::numbers::pi : 2 * std::numbers::pi) - angle_sum[v];
    return defect;
}

namespace {

// Gᵀ (|V| x 2|F|) weighted per face: column 2f + c holds weight[f] times component c of the
// gradients of face f's hat functions, rows ascending, corners at one vertex (Δ-complexes) summed
// in corner order. Each column is one face's, so it is built in place (from triplets, gradient
// took 3x and divergence 10x longer on 1M faces); gradient() is this transposed, divergence()
// this with weight -area.
Eigen::SparseMatrix<double> weighted_gradient_transpose(const Triangulation& t, const Eigen::VectorXd* weight) {
    require_sizes(t);
    const int nf = t.num_faces();
    Eigen::SparseMatrix<double> m(t.num_vertices, 2 * nf);
    int* outer = m.outerIndexPtr();
    outer[0] = 0;
    for (int f = 0; f < nf; ++f) {
        const int a = t.F(f, 0), b = t.F(f, 1), c = t.F(f, 2);
        const int distinct = 1 + (b != a) + (c != a && c != b);
        outer[2 * f + 1] = outer[2 * f] + distinct;
        outer[2 * f + 2] = outer[2 * f + 1] + distinct;
    }
    m.resizeNonZeros(outer[2 * nf]);
    int* inner = m.innerIndexPtr();
    double* value = m.valuePtr();
    detail::prefault(inner, sizeof(int) * static_cast<size_t>(outer[2 * nf]));
    detail::prefault(value, sizeof(double) * static_cast<size_t>(outer[2 * nf]));
#pragma omp parallel for schedule(static) if (nf >= kMinParallel)
    for (int f = 0; f < nf; ++f) {
        detail::prefetch_sides_ahead(t, f);
        const double l0 = t.side(f, 0), l1 = t.side(f, 1), l2 = t.side(f, 2);
        const double twice_area = 2 * triangle_area(l0, l1, l2);
        // Corner 2 sits at (x, 2·area/l2); cosine numerators give x and l2 - x without cancellation.
        const double grad[3][2] = {{-1 / l2, -cosine_numerator(l1, l0, l2) / (2 * twice_area * l2)},
                                   {1 / l2, -cosine_numerator(l0, l1, l2) / (2 * twice_area * l2)},
                                   {0.0, l2 / twice_area}};
        // Corners by vertex (stable, so equal vertices keep corner order), then merged.
        int order[3] = {0, 1, 2};
        const auto vertex = [&](int k) { return t.F(f, k); };
        if (vertex(order[1]) < vertex(order[0])) std::swap(order[0], order[1]);
        if (vertex(order[2]) < vertex(order[1])) std::swap(order[1], order[2]);
        if (vertex(order[1]) < vertex(order[0])) std::swap(order[0], order[1]);
        for (int c = 0; c < 2; ++c) {
            int n = outer[2 * f + c] - 1;
            for (int i = 0; i < 3; ++i) {
                const int k = order[i];
                if (i > 0 && vertex(k) == vertex(order[i - 1])) {
                    value[n] += grad[k][c];
                } else {
                    inner[++n] = vertex(k);
                    value[n] = grad[k][c];
                }
            }
            if (weight)
                for (int j = outer[2 * f + c]; j <= n; ++j) value[j] = (*weight)[f] * value[j];
        }
    }
    return m;
}

}  // namespace

Eigen::SparseMatrix<double> gradient(const Triangulation& t) {
    return Eigen::SparseMatrix<double>(weighted_gradient_transpose(t, nullptr).transpose());
}

Eigen::SparseMatrix<double> divergence(const Triangulation& t) {
    const Eigen::VectorXd weight = -face_areas(t);
    return weighted_gradient_transpose(t, &weight);
}

}  // namespace sdmesh
