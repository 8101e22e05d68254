// The internal flip/split connectivity: every edit leaves a valid, consistently oriented
// triangulation whose edge ids agree with the faces.

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "halfedge.hpp"
#include "sdmesh/shapes.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

// Lengths from positions for the current connectivity, then the full Triangulation check.
Triangulation checked(const HalfedgeMesh& mesh, const Eigen::MatrixX3d& V) {
    Eigen::VectorXd length(mesh.num_edges());
    for (int e = 0; e < mesh.num_edges(); ++e) {
        const int h = mesh.halfedge(e);
        length[e] = (V.row(mesh.tail(h)) - V.row(mesh.head(h))).norm();
    }
    Triangulation t = mesh.to_triangulation(length);
    t.check();
    return t;
}

MeshInfo info_of(const HalfedgeMesh& mesh, const Eigen::MatrixX3d& V) {
    return validate(TriangleMesh{V, mesh.faces()});
}

std::set<std::array<int, 3>> face_set(const Eigen::MatrixX3i& F) {
    std::set<std::array<int, 3>> faces;
    for (int f = 0; f < F.rows(); ++f) {
        std::array<int, 3> key = {F(f, 0), F(f, 1), F(f, 2)};
        std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());  // keeps orientation
        faces.insert(key);
    }
    return faces;
}

TriangleMesh test_pillow() {
    TriangleMesh m;
    m.V.resize(3, 3);
    m.V << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(0.75), 0;
    m.F.resize(2, 3);
    m.F << 0, 1, 2, 0, 2, 1;
    return m;
}

TEST(HalfedgeMesh, RoundTripKeepsTheTriangulation) {
    const TriangleMesh sphere = make_icosphere(1);
    const Triangulation t = Triangulation::from_mesh(sphere);
    const Triangulation back = checked(HalfedgeMesh(t), sphere.V);
    EXPECT_EQ(back.F, t.F);
    EXPECT_EQ(back.E, t.E);
    EXPECT_EQ(back.face_edge, t.face_edge);
    EXPECT_EQ(back.edge_halfedges, t.edge_halfedges);
}

TEST(HalfedgeMesh, FlipsKeepAValidOrientedSurface) {
    const TriangleMesh sphere = make_icosphere(2);
    HalfedgeMesh mesh(Triangulation::from_mesh(sphere));
    const auto original = face_set(mesh.faces());
    std::mt19937 rng(3);
    for (int i = 0; i < 200; ++i) {
        const int e = static_cast<int>(rng() % mesh.num_edges());
        const int h = mesh.halfedge(e);
        const int r = mesh.opposite_vertex(h), s = mesh.opposite_vertex(mesh.twin(h));
        if (mesh.has_diagonal(h)) continue;  // would duplicate an edge
        mesh.flip(e);
        const int g = mesh.halfedge(e);
        EXPECT_EQ(std::minmax(mesh.tail(g), mesh.head(g)), std::minmax(r, s));
        EXPECT_FALSE(mesh.has_diagonal(g));  // the old edge is gone
        checked(mesh, sphere.V);
        const MeshInfo info = info_of(mesh, sphere.V);
        ASSERT_TRUE(info.manifold());
        ASSERT_EQ(info.orientation_conflicts, 0);
        ASSERT_EQ(info.euler_characteristic, 2);
    }
    EXPECT_NE(face_set(mesh.faces()), original);
}

TEST(HalfedgeMesh, FlipTwiceRestoresTheFaces) {
    const TriangleMesh grid = make_grid(3, 3);
    HalfedgeMesh mesh(Triangulation::from_mesh(grid));
    const auto original = face_set(mesh.faces());
    for (int e = 0; e < mesh.num_edges(); ++e) {
        if (mesh.is_boundary_edge(e)) continue;
        mesh.flip(e);
        EXPECT_NE(face_set(mesh.faces()), original);
        mesh.flip(e);
        EXPECT_EQ(face_set(mesh.faces()), original) << "edge " << e;
    }
}

TEST(HalfedgeMesh, SplitsAddTheRightElements) {
    const TriangleMesh grid = make_grid(4, 3);
    HalfedgeMesh mesh(Triangulation::from_mesh(grid));
    Eigen::MatrixX3d V = grid.V;
    std::mt19937 rng(9);
    for (int i = 0; i < 60; ++i) {
        const int e = static_cast<int>(rng() % mesh.num_edges());
        const int h = mesh.halfedge(e);
        const int p = mesh.tail(h), q = mesh.head(h);
        const bool boundary = mesh.is_boundary_edge(e);
        const int faces = mesh.num_faces(), edges = mesh.num_edges();
        const int x = mesh.split(e);
        EXPECT_EQ(x, V.rows());
        V.conservativeResize(V.rows() + 1, 3);
        V.row(x) = 0.5 * (V.row(p) + V.row(q));
        EXPECT_EQ(mesh.num_faces(), faces + (boundary ? 1 : 2));
        EXPECT_EQ(mesh.num_edges(), edges + (boundary ? 2 : 3));
        const int kept = mesh.halfedge(e);  // e is now p-x
        EXPECT_EQ(std::minmax(mesh.tail(kept), mesh.head(kept)), std::minmax(p, x));
        const int other = mesh.halfedge(edges);  // the first new edge is x-q
        EXPECT_EQ(std::minmax(mesh.tail(other), mesh.head(other)), std::minmax(x, q));
        checked(mesh, V);
        const MeshInfo info = info_of(mesh, V);
        ASSERT_TRUE(info.manifold());
        ASSERT_EQ(info.orientation_conflicts, 0);
        ASSERT_EQ(info.euler_characteristic, 1);
        ASSERT_EQ(info.boundary_loops, 1);
    }
}

// merge() undoes split(), on interior and boundary edges: the original faces come back, glued
// as before under the original edge ids, and everything the splits added is marked removed.
TEST(HalfedgeMesh, MergesUndoSplits) {
    const TriangleMesh grid = make_grid(4, 3);
    HalfedgeMesh mesh(Triangulation::from_mesh(grid));
    const auto original = face_set(mesh.faces());
    const int original_edges = mesh.num_edges();
    struct Split {
        int e, p, x;
    };
    std::vector<Split> splits;
    std::mt19937 rng(5);
    for (int i = 0; i < 30; ++i) {
        const int e = static_cast<int>(rng() % original_edges);
        const int p = mesh.tail(mesh.halfedge(e));
        splits.push_back({e, p, mesh.split(e)});
    }
    // Undo the newest first: then each x has its four (boundary: three) neighbours again.
    for (auto it = splits.rbegin(); it != splits.rend(); ++it) {
        int h = mesh.halfedge(it->e);
        if (mesh.head(h) != it->x) h = mesh.twin(h);
        ASSERT_GE(h, 0);
        ASSERT_EQ(mesh.tail(h), it->p);
        mesh.merge(h);
    }
    EXPECT_EQ(face_set(mesh.faces()), original);
    for (int e = 0; e < mesh.num_edges(); ++e) EXPECT_EQ(mesh.is_removed_edge(e), e >= original_edges) << e;
    const Triangulation t = Triangulation::from_mesh(grid);
    for (int f = 0; f < mesh.num_faces(); ++f) {
        if (mesh.is_removed_face(f)) continue;
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * f + k, e = mesh.edge(h), twin = mesh.twin(h);
            ASSERT_FALSE(mesh.is_removed_edge(e));
            EXPECT_EQ(std::minmax(mesh.tail(h), mesh.head(h)), std::minmax(t.E(e, 0), t.E(e, 1))) << e;
            EXPECT_TRUE(mesh.halfedge(e) == h || mesh.halfedge(e) == twin) << e;
            if (twin < 0) continue;
            EXPECT_FALSE(mesh.is_removed_face(twin / 3));
            EXPECT_EQ(mesh.twin(twin), h);
            EXPECT_EQ(mesh.edge(twin), e);
        }
    }
}

// Every record of the mesh, for exact comparisons.
struct Records {
    int vertices;
    std::vector<int> corners, twins, edges, halfedges;
    std::vector<double> lengths;
    bool operator==(const Records&) const = default;
};

Records records(const HalfedgeMesh& mesh) {
    Records r{mesh.num_vertices(), {}, {}, {}, {}, {}};
    for (int h = 0; h < 3 * mesh.num_faces(); ++h) {
        r.corners.push_back(mesh.corner(h / 3, h % 3));
        r.twins.push_back(mesh.twin(h));
        r.edges.push_back(mesh.edge(h));
        r.lengths.push_back(mesh.side_length(h));
    }
    for (int e = 0; e < mesh.num_edges(); ++e) r.halfedges.push_back(mesh.halfedge(e));
    return r;
}

// A rolled-back trial of flips, splits, merges and side lengths leaves every record as it was;
// a committed one keeps its changes.
TEST(HalfedgeMesh, RollbackRestoresEveryRecord) {
    const TriangleMesh grid = make_grid(5, 4);
    HalfedgeMesh mesh(Triangulation::from_mesh(grid));
    std::mt19937 rng(11);
    for (int i = 0; i < 10; ++i) mesh.split(static_cast<int>(rng() % mesh.num_edges()));
    for (int trial = 0; trial < 20; ++trial) {
        const Records before = records(mesh);
        mesh.begin_trial();
        std::vector<std::pair<int, int>> splits;  // (edge, new vertex)
        for (int i = 0; i < 8; ++i) {
            const int e = static_cast<int>(rng() % mesh.num_edges());
            if (mesh.is_removed_edge(e)) continue;
            const int h = mesh.halfedge(e);
            switch (rng() % 3) {
                case 0:
                    if (!mesh.is_boundary_edge(e) && !mesh.has_diagonal(h))
                        mesh.flip(e);
                    break;
                case 1: splits.emplace_back(e, mesh.split(e)); break;
                default: mesh.set_side_length(h, 0.25 * i); break;
            }
        }
        // The last split, if nothing came after it, can be merged back within the trial.
        if (!splits.empty()) {
            const auto [e, x] = splits.back();
            int h = mesh.halfedge(e);
            if (mesh.head(h) != x) h = mesh.twin(h);
            if (h >= 0 && mesh.head(h) == x && mesh.num_vertices() == x + 1) mesh.merge(h);
        }
        ASSERT_NE(records(mesh), before) << trial;
        if (trial % 4 == 3) {
            mesh.commit();
            continue;
        }
        mesh.rollback();
        ASSERT_EQ(records(mesh), before) << trial;
    }
    Eigen::MatrixX3d V = Eigen::MatrixX3d::Zero(mesh.num_vertices(), 3);
    V.topRows(grid.V.rows()) = grid.V;
    const MeshInfo info = info_of(mesh, V);  // the committed trials left a valid surface
    EXPECT_TRUE(info.manifold());
    EXPECT_EQ(info.orientation_conflicts, 0);
    EXPECT_EQ(info.euler_characteristic, 1);
}

TEST(HalfedgeMesh, EdgeQueriesWalkTheWholeFan) {
    // has_diagonal against the neighbours listed from the faces, for every interior halfedge.
    const auto expect_diagonals_found = [](const HalfedgeMesh& mesh, const std::string& name) {
        const Eigen::MatrixX3i F = mesh.faces();
        std::vector<std::set<int>> neighbours(mesh.num_vertices());
        for (int f = 0; f < F.rows(); ++f)
            for (int k = 0; k < 3; ++k) {
                neighbours[F(f, k)].insert(F(f, (k + 1) % 3));
                neighbours[F(f, (k + 1) % 3)].insert(F(f, k));
            }
        int joined = 0;
        for (int h = 0; h < 3 * mesh.num_faces(); ++h) {
            if (mesh.twin(h) < 0) continue;
            const int r = mesh.opposite_vertex(h), s = mesh.opposite_vertex(mesh.twin(h));
            const bool expected = neighbours[r].count(s) > 0;
            joined += expected;
            EXPECT_EQ(mesh.has_diagonal(h), expected) << name << ": " << r << " " << s;
        }
        return joined;
    };
    // In the tetrahedron every edge's opposite vertices are joined; in the icosphere and the
    // grid (open fans at its sides) none are.
    TriangleMesh tetrahedron;
    tetrahedron.V = Eigen::MatrixX3d::Identity(4, 3);
    tetrahedron.F.resize(4, 3);
    tetrahedron.F << 0, 1, 2, 0, 3, 1, 1, 3, 2, 0, 2, 3;
    EXPECT_EQ(expect_diagonals_found(HalfedgeMesh(Triangulation::from_mesh(tetrahedron)), "tetrahedron"), 12);
    EXPECT_EQ(expect_diagonals_found(HalfedgeMesh(Triangulation::from_mesh(make_icosphere(1))), "icosphere"), 0);
    EXPECT_EQ(expect_diagonals_found(HalfedgeMesh(Triangulation::from_mesh(make_grid(4, 4))), "grid"), 0);
    // Random flips leave vertices of degree 3 to 12 or so, closed fans on the sphere and open
    // ones at the cylinder's rims, whose joined neighbours lie anywhere round them (where the
    // two ways round meet, too).
    for (const auto& [name, m] : {std::pair{"sphere", make_icosphere(1)}, std::pair{"cylinder", make_cylinder(6, 3)}}) {
        HalfedgeMesh scrambled(Triangulation::from_mesh(m));
        std::mt19937 rng(5);
        int joined = 0;
        for (int i = 0; i < 400; ++i) {
            const int e = static_cast<int>(rng() % scrambled.num_edges());
            if (!scrambled.is_boundary_edge(e) && !scrambled.has_diagonal(scrambled.halfedge(e))) scrambled.flip(e);
            if (i % 40 == 39) joined += expect_diagonals_found(scrambled, std::string(name) + ", flip " + std::to_string(i));
        }
        EXPECT_GT(joined, 0) << name;
    }
}

// The pillow: two equilateral triangles glued along all three sides. Flipping a side joins the
// two opposite corners, which are the same vertex: a self-edge, and each face becomes glued to
// itself along another side.
TEST(HalfedgeMesh, FlipToASelfEdgeGivesAConsistentDeltaComplex) {
    const TriangleMesh pillow = test_pillow();
    HalfedgeMesh mesh(Triangulation::from_mesh(pillow));
    const int e = 0;  // (0, 1), opposite vertex 2 on both sides
    mesh.flip(e);
    const int h = mesh.halfedge(e);
    EXPECT_EQ(mesh.tail(h), 2);
    EXPECT_EQ(mesh.head(h), 2);
    Eigen::VectorXd length = Eigen::VectorXd::Ones(mesh.num_edges());
    length[e] = std::sqrt(3.0);  // twice the height of the unit equilateral triangle
    const Triangulation t = mesh.to_triangulation(length);
    t.check();
    EXPECT_EQ(t.E.row(e), Eigen::RowVector2i(2, 2));
    // On a closed oriented surface every edge is run along once in each direction, so its signs
    // sum to zero (the rows of d1 add up to 0); that includes the self-edge.
    Eigen::VectorXi sign_sum = Eigen::VectorXi::Zero(t.num_edges());
    for (int f = 0; f < t.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) sign_sum[t.face_edge(f, k)] += t.face_edge_sign(f, k);
    EXPECT_EQ(sign_sum, Eigen::VectorXi::Zero(t.num_edges()));
    EXPECT_EQ(t.face_edge_sign(t.edge_halfedges(e, 0) / 3, t.edge_halfedges(e, 0) % 3), 1);

    mesh.flip(e);  // back to the pillow
    EXPECT_EQ(face_set(mesh.faces()), face_set(pillow.F));
    EXPECT_EQ(std::minmax(mesh.tail(mesh.halfedge(e)), mesh.head(mesh.halfedge(e))), std::minmax(0, 1));
}

}  // namespace
}  // namespace sdmesh
