#include "sdmesh/triangulation.hpp"

#include <cmath>
#include <string>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/topology.hpp"
#include "number_text.hpp"
#include "prefault.hpp"

namespace sdmesh {
namespace {

// Connectivity from an edge table; lengths are left to the caller.
Triangulation connectivity(const Eigen::MatrixX3i& F, int num_vertices) {
    const int num_faces = static_cast<int>(F.rows());
    for (int f = 0; f < num_faces; ++f)
        for (int k = 0; k < 3; ++k)
            if (F(f, k) < 0 || F(f, k) >= num_vertices)
                throw InvalidMeshError("face " + std::to_string(f) + " references vertex " + std::to_string(F(f, k)) +
                                       ", but there are " + std::to_string(num_vertices) + " vertices");
    for (int f = 0; f < num_faces; ++f)
        if (has_repeated_index(F, f))
            throw InvalidMeshError("face " + std::to_string(f) + " has a repeated vertex index");
    EdgeTable table = build_edge_table(F, num_vertices, NonmanifoldVertices::skip);
    for (int e = 0; e < table.num_edges(); ++e)
        if (table.face_count[e] > 2)
            throw InvalidMeshError("edge (" + std::to_string(table.E(e, 0)) + ", " + std::to_string(table.E(e, 1)) +
                                   ") has " + std::to_string(table.face_count[e]) + " faces");
    Triangulation t;
    t.num_vertices = num_vertices;
    t.F = F;
    t.E = std::move(table.E);
    t.face_edge = std::move(table.face_edge);
    t.edge_halfedges = std::move(table.edge_halfedges);
    t.face_edge_sign.resize(num_faces, 3);
    detail::prefault(t.face_edge_sign);
    for (int f = 0; f < num_faces; ++f)
        for (int k = 0; k < 3; ++k)
            t.face_edge_sign(f, k) = F(f, (k + 1) % 3) == t.E(t.face_edge(f, k), 0) ? 1 : -1;
    return t;
}

// Positive finite lengths and faces of positive area: all that a triangulation assembled by
// connectivity() can still get wrong.
void check_geometry(const Triangulation& t) {
    auto fail = [](const std::string& what) { throw InvalidMeshError("triangulation: " + what); };
    const int ne = t.num_edges(), nf = t.num_faces();
    const auto& length = t.length;
    for (int e = 0; e < ne; ++e)
        if (!(length[e] > 0) || !std::isfinite(length[e]))
            fail("edge " + std::to_string(e) + " has length " + detail::number_text(length[e]));
    // A face of positive area by its coordinates can still be flat by its side lengths: a corner
    // within rounding of 180° (validate() judges by coordinates).
    for (int f = 0; f < nf; ++f)
        if (!(triangle_area(t.side(f, 0), t.side(f, 1), t.side(f, 2)) > 0))
            fail("face " + std::to_string(f) + " has zero area by its side lengths " +
                 detail::number_text(t.side(f, 0)) + ", " + detail::number_text(t.side(f, 1)) + " and " +
                 detail::number_text(t.side(f, 2)) +
                 " (a corner within rounding of 180 degrees; conversion, by sdmesh convert or a solver's "
                 "--convert split, can split such a face away)");
}

}  // namespace

Triangulation Triangulation::from_mesh(const TriangleMesh& mesh) {
    require_finite_positions(mesh);
    require_supported_extent(mesh);
    Triangulation t = connectivity(mesh.F, mesh.num_vertices());
    t.length.resize(t.num_edges());
    detail::prefault(t.length);
    for (int e = 0; e < t.num_edges(); ++e)
        t.length[e] = distance(mesh.V.row(t.E(e, 0)).transpose(), mesh.V.row(t.E(e, 1)).transpose());
    check_geometry(t);
    return t;
}

Triangulation Triangulation::from_side_lengths(const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& side_length,
                                               int num_vertices) {
    if (side_length.rows() != F.rows())
        throw InvalidMeshError("from_side_lengths: " + std::to_string(side_length.rows()) + " rows of lengths for " +
                               std::to_string(F.rows()) + " faces");
    Triangulation t = connectivity(F, num_vertices);
    t.length.resize(t.num_edges());
    for (int e = 0; e < t.num_edges(); ++e) {
        const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
        const double l0 = side_length(h0 / 3, h0 % 3);
        if (h1 >= 0) {
            const double l1 = side_length(h1 / 3, h1 % 3);
            if (!(std::abs(l0 - l1) <= 1e-12 * std::max(l0, l1)))
                throw InvalidMeshError("edge (" + std::to_string(t.E(e, 0)) + ", " + std::to_string(t.E(e, 1)) +
                                       ") has length " + detail::number_text(l0) + " in face " + std::to_string(h0 / 3) +
                                       " but " + detail::number_text(l1) + " in face " + std::to_string(h1 / 3));
        }
        t.length[e] = l0;
    }
    check_geometry(t);
    return t;
}

void Triangulation::check() const {
    auto fail = [](const std::string& what) { throw InvalidMeshError("triangulation: " + what); };
    const int nf = num_faces(), ne = num_edges();
    if (face_edge.rows() != nf || face_edge_sign.rows() != nf || edge_halfedges.rows() != ne || length.size() != ne)
        fail("array sizes do not match " + std::to_string(nf) + " faces and " + std::to_string(ne) + " edges");
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) {
            const int e = face_edge(f, k);
            if (F(f, k) < 0 || F(f, k) >= num_vertices) fail("face " + std::to_string(f) + " has a bad vertex index");
            if (e < 0 || e >= ne) fail("face " + std::to_string(f) + " has a bad edge index");
            const int from = F(f, (k + 1) % 3), to = F(f, (k + 2) % 3);
            const bool forward = face_edge_sign(f, k) > 0;
            if ((forward ? from : to) != E(e, 0) || (forward ? to : from) != E(e, 1))
                fail("side " + std::to_string(k) + " of face " + std::to_string(f) + " does not match edge " +
                     std::to_string(e));
            const int h = 3 * f + k;
            if (edge_halfedges(e, 0) != h && edge_halfedges(e, 1) != h)
                fail("edge " + std::to_string(e) + " does not list halfedge " + std::to_string(h));
        }
    check_geometry(*this);
}

}  // namespace sdmesh
