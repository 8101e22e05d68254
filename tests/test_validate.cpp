// Edge table, validation counts and repairs on meshes made in code.

#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "meshes.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/shapes.hpp"
#include "sdmesh/triangulation.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

using test::make_mesh;
using test::total_area;  // repairs must not change it

// What every repaired mesh here must be: `faces` faces, none of zero area, a manifold with the
// input's surface area.
MeshInfo expect_mended(const TriangleMesh& repaired, int faces, double area, double tolerance) {
    const MeshInfo info = validate(repaired);
    EXPECT_EQ(info.faces, faces);
    EXPECT_EQ(info.zero_area_faces, 0);
    EXPECT_TRUE(info.manifold());
    EXPECT_NEAR(total_area(repaired), area, tolerance);
    return info;
}

// A repaired mesh repairs to itself: the same mesh, and nothing done.
void expect_repairs_to_itself(const TriangleMesh& repaired) {
    RepairReport again;
    const TriangleMesh twice = repair(repaired, {}, &again);
    EXPECT_EQ(twice.V, repaired.V);
    EXPECT_EQ(twice.F, repaired.F);
    EXPECT_TRUE(again == RepairReport{}) << "merged " << again.merged_vertices << ", split " << again.split_vertices
                                         << ", dropped " << again.dropped_vertices << " vertices";
}

TEST(EdgeTable, LexicographicWithFaceIncidence) {
    const TriangleMesh quad = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
    const EdgeTable edges = build_edge_table(quad.F, 4);
    Eigen::MatrixX2i expected(5, 2);
    expected << 0, 1, 0, 2, 0, 3, 1, 2, 2, 3;
    EXPECT_EQ(edges.E, expected);
    EXPECT_EQ(edges.face_count, (std::vector<int>{1, 2, 1, 1, 1}));
    // face_edge(f, k) is opposite corner k.
    for (int f = 0; f < 2; ++f)
        for (int k = 0; k < 3; ++k) {
            const int e = edges.face_edge(f, k);
            const int a = quad.F(f, (k + 1) % 3), b = quad.F(f, (k + 2) % 3);
            EXPECT_EQ(edges.E(e, 0), std::min(a, b));
            EXPECT_EQ(edges.E(e, 1), std::max(a, b));
        }
    EXPECT_EQ(edges.edge_halfedges(1, 0), 3 * 0 + 1);  // diagonal (0,2): opposite corner 1 of face 0
    EXPECT_EQ(edges.edge_halfedges(1, 1), 3 * 1 + 2);  // and corner 2 of face 1
}

TEST(Validate, ClosedSurfacesHaveTheirGenus) {
    const MeshInfo sphere = validate(make_icosphere(2));
    EXPECT_EQ(sphere.vertices, 162);
    EXPECT_EQ(sphere.faces, 320);
    EXPECT_EQ(sphere.edges, 480);
    EXPECT_EQ(sphere.euler_characteristic, 2);
    EXPECT_EQ(sphere.genus, 0);
    EXPECT_EQ(sphere.components, 1);
    EXPECT_EQ(sphere.boundary_loops, 0);
    EXPECT_TRUE(sphere.manifold());
    EXPECT_TRUE(sphere.orientable);
    EXPECT_EQ(sphere.orientation_conflicts, 0);

    // A torus: a cylinder whose top ring is glued to its bottom ring.
    TriangleMesh torus = make_cylinder(8, 6);
    for (int f = 0; f < torus.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            if (torus.F(f, k) >= 6 * 8) torus.F(f, k) -= 6 * 8;
    const MeshInfo info = validate(torus);
    EXPECT_EQ(info.unreferenced_vertices, 8);
    EXPECT_EQ(info.euler_characteristic, 0);
    EXPECT_EQ(info.genus, 1);
    EXPECT_EQ(info.boundary_edges, 0);
}

TEST(Validate, BoundaryLoopsAndComponents) {
    const MeshInfo cylinder = validate(make_cylinder(10, 3));
    EXPECT_EQ(cylinder.boundary_loops, 2);
    EXPECT_EQ(cylinder.boundary_edges, 20);
    EXPECT_EQ(cylinder.genus, 0);

    // Two disjoint grids.
    TriangleMesh a = make_grid(3, 3), two;
    two.V.resize(2 * a.num_vertices(), 3);
    two.V << a.V, a.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
    two.F.resize(2 * a.num_faces(), 3);
    two.F << a.F, a.F.array() + a.num_vertices();
    const MeshInfo info = validate(two);
    EXPECT_EQ(info.components, 2);
    EXPECT_EQ(info.boundary_loops, 2);
    EXPECT_EQ(info.euler_characteristic, 2);
    EXPECT_EQ(info.genus, 0);
}

TEST(Validate, NonManifoldEdgeAndBowTie) {
    const TriangleMesh fin = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                                       {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    const MeshInfo a = validate(fin);
    EXPECT_EQ(a.nonmanifold_edges, 1);
    EXPECT_EQ(a.first_nonmanifold_edge, Eigen::Vector2i(0, 1));
    EXPECT_EQ(a.nonmanifold_vertices, 2);  // both ends of the fin edge have three fans
    EXPECT_EQ(a.genus, -1);
    EXPECT_THROW(require_manifold(a, "test"), InvalidMeshError);

    // Two triangles touching at vertex 0 only.
    const TriangleMesh bowtie = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                          {{0, 1, 2}, {0, 3, 4}});
    const MeshInfo b = validate(bowtie);
    EXPECT_EQ(b.nonmanifold_edges, 0);
    EXPECT_EQ(b.nonmanifold_vertices, 1);
    EXPECT_EQ(b.first_nonmanifold_vertex, 0);
    EXPECT_EQ(b.components, 1);
    EXPECT_FALSE(b.manifold());
}

TEST(Validate, MoebiusStripIsNotOrientable) {
    // A strip of 6 quads whose ends are glued with a half twist.
    const int n = 6;
    TriangleMesh strip;
    strip.V.resize(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        const double t = 2 * std::numbers::pi * i / n;
        for (int side = 0; side < 2; ++side) {
            const double w = side ? 0.3 : -0.3;
            strip.V.row(2 * i + side) << (1 + w * std::cos(t / 2)) * std::cos(t),
                (1 + w * std::cos(t / 2)) * std::sin(t), w * std::sin(t / 2);
        }
    }
    strip.F.resize(2 * n, 3);
    for (int i = 0; i < n; ++i) {
        int a = 2 * i, b = 2 * i + 1, c = 2 * (i + 1) + 1, d = 2 * (i + 1);
        if (i == n - 1) c = 0, d = 1;  // the half twist swaps the sides
        strip.F.row(2 * i) << a, d, c;
        strip.F.row(2 * i + 1) << a, c, b;
    }
    const MeshInfo info = validate(strip);
    EXPECT_TRUE(info.manifold());
    EXPECT_FALSE(info.orientable);
    EXPECT_EQ(info.genus, -1);
    EXPECT_EQ(info.boundary_loops, 1);
    RepairReport report;
    repair(strip, {}, &report);
    EXPECT_EQ(report.non_orientable_components, 1);
    EXPECT_EQ(report.flipped_faces, 0);
    // What repair cannot fix is not sent to repair.
    try {
        require_oriented_manifold(info, "convert");
        ADD_FAILURE() << "no error";
    } catch (const InvalidMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("not orientable"), std::string::npos) << e.what();
    }
}

TEST(Validate, DefectsAreCounted) {
    TriangleMesh mesh = make_mesh(
        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 0}, {2, 2, 0}, {std::nan(""), 0, 0}, {0.5, 0.5, 0}},
        {{0, 1, 2}, {1, 3, 2}, {2, 1, 0}, {4, 1, 1}, {0, 3, 7}});
    const MeshInfo info = validate(mesh);
    EXPECT_EQ(info.repeated_index_faces, 1);       // face 3
    EXPECT_EQ(info.first_repeated_index_face, 3);
    EXPECT_EQ(info.duplicate_faces, 1);            // face 2 repeats face 0
    EXPECT_EQ(info.zero_area_faces, 1);            // face 4 is collinear
    EXPECT_EQ(info.degenerate_faces, 2);
    EXPECT_EQ(info.duplicate_vertex_positions, 1); // vertex 4 sits on vertex 0
    EXPECT_EQ(info.unreferenced_vertices, 2);      // 5 and 6
    EXPECT_EQ(info.non_finite_vertices, 1);
    EXPECT_EQ(info.first_non_finite_vertex, 6);
    EXPECT_EQ(info.nonmanifold_edges, 1);          // (1, 2) lies in faces 0, 1 and 2
    EXPECT_EQ(info.orientation_conflicts, 0);      // face 2 is face 0 reversed: consistent
    EXPECT_THROW(require_manifold(info, "test"), InvalidMeshError);
}

// convert and decimate count the defects alone: the same defects and first offenders as the
// whole analysis, the statistics they skip left unset.
TEST(Validate, TheDefectsScopeFindsTheSameDefects) {
    const TriangleMesh defective = make_mesh(
        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 0}, {2, 2, 0}, {std::nan(""), 0, 0}, {0.5, 0.5, 0}},
        {{0, 1, 2}, {1, 3, 2}, {2, 1, 0}, {4, 1, 1}, {0, 3, 7}});
    const TriangleMesh bowtie = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                          {{0, 1, 2}, {0, 3, 4}});
    TriangleMesh misoriented = make_icosphere(1);
    misoriented.F.row(5) = misoriented.F.row(5).reverse().eval();
    for (const TriangleMesh* mesh : std::initializer_list<const TriangleMesh*>{&defective, &bowtie, &misoriented}) {
        const EdgeTable edges = build_edge_table(mesh->F, mesh->num_vertices());
        const MeshInfo all = validate(*mesh, edges), defects = validate(*mesh, edges, ValidateScope::defects);
        EXPECT_EQ(first_defect(defects), first_defect(all));
        EXPECT_EQ(defects.non_finite_vertices, all.non_finite_vertices);
        EXPECT_EQ(defects.repeated_index_faces, all.repeated_index_faces);
        EXPECT_EQ(defects.zero_area_faces, all.zero_area_faces);
        EXPECT_EQ(defects.first_zero_area_face, all.first_zero_area_face);
        EXPECT_EQ(defects.nonmanifold_edges, all.nonmanifold_edges);
        EXPECT_EQ(defects.nonmanifold_vertices, all.nonmanifold_vertices);
        EXPECT_EQ(defects.orientation_conflicts, all.orientation_conflicts);
        EXPECT_EQ(defects.orientable, all.orientable);
        EXPECT_EQ(defects.duplicate_faces, 0);
        EXPECT_EQ(defects.duplicate_vertex_positions, 0);
        EXPECT_EQ(defects.components, 0);
        EXPECT_EQ(defects.genus, -1);
    }
    EXPECT_GT(validate(misoriented).orientation_conflicts, 0);
}

// A cap 8e8 long whose apex lies 0.8 (1e-9 of the length) off its long side: its short sides
// sum to the long one in rounding, so an area from the lengths was 0. Its area is 5e-10 of the
// long side squared, no zero-area face: repair must not flip it (that moved the surface) and
// validate must not count it.
TEST(Validate, ZeroAreaIsJudgedFromCoordinatesNotSideLengths) {
    const TriangleMesh mesh = make_mesh({{0, 0, 0}, {8e8, 0, 0}, {2e8, 0.8, 0}, {3e8, -2e8, 1e8}},
                                        {{0, 1, 2}, {1, 0, 3}, {0, 2, 3}, {2, 1, 3}});
    EXPECT_EQ(validate(mesh).zero_area_faces, 0);
    RepairReport report;
    repair(mesh, {}, &report);
    EXPECT_EQ(report.flipped_caps, 0);
    // By its side lengths (2e8 + 6e8 = 8e8 in rounding) it has none: the operators, which take
    // their angles from the lengths, refuse it and say so.
    try {
        (void)Triangulation::from_mesh(mesh);
        ADD_FAILURE() << "no InvalidMeshError";
    } catch (const InvalidMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("face 0 has zero area by its side lengths 6e+08, 2e+08 and 8e+08"),
                  std::string::npos)
            << e.what();
    }
    // Exactly on the side it is a cap, and the flip keeps the area.
    TriangleMesh cap = mesh;
    cap.V(2, 1) = 0;
    EXPECT_EQ(validate(cap).zero_area_faces, 1);
}

TEST(Validate, IndexOutOfRangeThrows) {
    TriangleMesh mesh = make_icosphere(0);
    mesh.F(0, 0) = -1;
    EXPECT_THROW(validate(mesh), InvalidMeshError);
    EXPECT_THROW(repair(mesh), InvalidMeshError);
}

TEST(Repair, RestoresAValidMesh) {
    // An icosphere written as a triangle soup with duplicated vertices, a duplicate face,
    // a repeated-index face, an unreferenced vertex and a third of the faces re-wound.
    const TriangleMesh sphere = make_icosphere(1);
    TriangleMesh soup;
    soup.V.resize(3 * sphere.num_faces() + 1, 3);
    soup.F.resize(sphere.num_faces() + 2, 3);
    for (int f = 0; f < sphere.num_faces(); ++f) {
        for (int k = 0; k < 3; ++k) soup.V.row(3 * f + k) = sphere.V.row(sphere.F(f, k));
        soup.F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
        if (f % 3 == 1) std::swap(soup.F(f, 1), soup.F(f, 2));  // re-wound
    }
    soup.V.row(3 * sphere.num_faces()) << 7, 7, 7;
    soup.F.row(sphere.num_faces()) = soup.F.row(0);
    soup.F.row(sphere.num_faces() + 1) << 0, 0, 1;

    int rewound = 0;
    for (int f = 1; f < sphere.num_faces(); f += 3) ++rewound;
    RepairReport report;
    const TriangleMesh repaired = repair(soup, {}, &report);
    EXPECT_EQ(report.merged_vertices, 3 * sphere.num_faces() - sphere.num_vertices());
    EXPECT_EQ(report.dropped_repeated_index_faces, 1);
    EXPECT_EQ(report.dropped_duplicate_faces, 1);
    EXPECT_EQ(report.flipped_faces, rewound);  // face 0 keeps its orientation
    EXPECT_EQ(repaired.num_vertices(), sphere.num_vertices());
    EXPECT_EQ(repaired.num_faces(), sphere.num_faces());
    const MeshInfo info = validate(repaired);
    EXPECT_TRUE(info.manifold());
    EXPECT_EQ(info.orientation_conflicts, 0);
    EXPECT_EQ(info.genus, 0);
    EXPECT_EQ(info.duplicate_vertex_positions, 0);
    EXPECT_EQ(info.unreferenced_vertices, 0);
    expect_repairs_to_itself(repaired);
    // Outward orientation is kept: positive signed volume.
    double volume = 0;
    for (int f = 0; f < repaired.num_faces(); ++f)
        volume += repaired.V.row(repaired.F(f, 0)).dot(
            repaired.V.row(repaired.F(f, 1)).cross(repaired.V.row(repaired.F(f, 2))));
    EXPECT_GT(volume, 0);
}

TEST(Repair, GivesEachFanAtANonManifoldVertexItsOwnCopy) {
    // Two octahedra touching at a vertex (a bow-tie vertex), and a book of three triangles on one
    // edge (an edge with three faces; both its vertices are non-manifold).
    const TriangleMesh octahedron = make_mesh(
        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
        {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
    TriangleMesh touching;
    touching.V.resize(11, 3);
    touching.V.topRows(6) = octahedron.V;
    // The second octahedron, moved by 2 along x: its vertex 1 (-x) is the first's vertex 0 (+x),
    // its others become 6, 7, ..., 10.
    const int second[6] = {6, 0, 7, 8, 9, 10};
    for (int v = 0; v < 6; ++v)
        if (v != 1) touching.V.row(second[v]) = octahedron.V.row(v) + Eigen::RowVector3d(2, 0, 0);
    touching.F.resize(16, 3);
    touching.F.topRows(8) = octahedron.F;
    for (int f = 0; f < 8; ++f)
        for (int k = 0; k < 3; ++k) touching.F(8 + f, k) = second[octahedron.F(f, k)];
    const MeshInfo before = validate(touching);
    ASSERT_EQ(before.nonmanifold_vertices, 1);
    ASSERT_EQ(before.first_nonmanifold_vertex, 0);
    RepairReport report;
    const TriangleMesh repaired = repair(touching, {}, &report);
    EXPECT_EQ(report.split_vertices, 1);
    const MeshInfo after = validate(repaired);
    EXPECT_TRUE(after.manifold());
    EXPECT_EQ(after.components, 2);
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.duplicate_vertex_positions, 1);  // the copy sits where the vertex was
    EXPECT_NEAR(total_area(repaired), total_area(touching), 1e-12);
    EXPECT_TRUE(convert(repaired).report.certificate.self_delaunay);
    expect_repairs_to_itself(repaired);
    // Merging the copy with the vertex would make the bow-tie again: two vertices at one point,
    // one in each octahedron, are left as they are.
    TriangleMesh apart = touching;
    apart.V.conservativeResize(12, 3);
    apart.V.row(11) = apart.V.row(0);
    for (int f = 8; f < 16; ++f)
        for (int k = 0; k < 3; ++k)
            if (apart.F(f, k) == 0) apart.F(f, k) = 11;
    const TriangleMesh left = repair(apart, {}, &report);
    EXPECT_TRUE(report == RepairReport{});
    EXPECT_EQ(left.V, apart.V);
    EXPECT_EQ(left.F, apart.F);

    const TriangleMesh book = make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0.2}, {0.5, 0, 1}},
                                        {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    ASSERT_EQ(validate(book).nonmanifold_edges, 1);
    const TriangleMesh pages = repair(book, {}, &report);
    const MeshInfo opened = validate(pages);
    EXPECT_TRUE(opened.manifold());
    EXPECT_EQ(opened.nonmanifold_edges, 0);
    EXPECT_EQ(report.split_vertices, 4);  // the edge's two vertices, once for two of the pages
    EXPECT_NEAR(total_area(pages), total_area(book), 1e-12);
    for (int v = 0; v < pages.num_vertices(); ++v) {  // every vertex where one of the book's was
        bool found = false;
        for (int w = 0; w < book.num_vertices(); ++w) found = found || pages.V.row(v) == book.V.row(w);
        EXPECT_TRUE(found) << "vertex " << v;
    }
    expect_repairs_to_itself(pages);
    // A zero-area cap as the third page: once it is dropped, the two others share the edge again.
    const TriangleMesh capped_book = make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0.2}, {0.5, 0, 0}},
                                               {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    const TriangleMesh two_pages = repair(capped_book, {}, &report);
    EXPECT_EQ(report.dropped_caps, 1);
    const MeshInfo joined = expect_mended(two_pages, 2, 0.5 + 0.5 * std::sqrt(1.04), 1e-12);
    EXPECT_EQ(joined.vertices, 4);
    EXPECT_EQ(joined.boundary_edges, 4);  // edge 0-1 is interior
    expect_repairs_to_itself(two_pages);

    RepairOptions keep;
    keep.split_nonmanifold_vertices = false;
    EXPECT_EQ(validate(repair(touching, keep)).nonmanifold_vertices, 1);
}

TEST(Repair, FlipsZeroAreaCapsAwayWithoutMovingTheSurface) {
    // An octahedron whose edge +x +y carries a vertex at its midpoint: the face below is split
    // there, and a cap (zero area, the new vertex inside its long side) closes the surface.
    const TriangleMesh octahedron = make_mesh(
        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
        {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
    TriangleMesh capped = octahedron;
    capped.V.conservativeResize(7, 3);
    capped.V.row(6) << 0.5, 0.5, 0;
    capped.F.conservativeResize(10, 3);
    capped.F.row(4) << 2, 6, 5;
    capped.F.row(8) << 6, 0, 5;
    capped.F.row(9) << 2, 0, 6;  // the cap
    ASSERT_EQ(validate(capped).zero_area_faces, 1);
    ASSERT_EQ(validate(capped).orientation_conflicts, 0);
    EXPECT_THROW((void)convert(capped), InvalidMeshError);

    RepairReport report;
    const TriangleMesh repaired = repair(capped, {}, &report);
    EXPECT_EQ(report.flipped_caps, 1);
    const MeshInfo info = validate(repaired);
    EXPECT_EQ(info.zero_area_faces, 0);
    EXPECT_TRUE(info.manifold());
    EXPECT_EQ(info.orientation_conflicts, 0);
    EXPECT_EQ(info.euler_characteristic, 2);
    // The same surface: the area and the enclosed volume of the octahedron (4√3 and 4/3).
    double volume = 0;
    for (int f = 0; f < repaired.num_faces(); ++f) {
        const Eigen::Vector3d a = repaired.V.row(repaired.F(f, 0)), b = repaired.V.row(repaired.F(f, 1)),
                              c = repaired.V.row(repaired.F(f, 2));
        volume += a.dot(b.cross(c)) / 6;
    }
    EXPECT_NEAR(total_area(repaired), 4 * std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(volume, 4.0 / 3.0, 1e-12);
    EXPECT_TRUE(convert(repaired).report.certificate.self_delaunay);
    expect_repairs_to_itself(repaired);

    // Kept on request.
    RepairOptions keep;
    keep.flip_caps = false;
    EXPECT_EQ(validate(repair(capped, keep)).zero_area_faces, 1);
}

TEST(Repair, CollapsesNeedles) {
    // The octahedron with +z pushed into the plane z = 0, 1e-11 beyond +y as seen from +x: face
    // +x +y +z is a needle (its short side +y +z is 7e-12 of its longest, 3.5e-12 of the diagonal:
    // not rounding), which no flip mends. Collapsing that side into +y (the smaller index) leaves
    // a double pyramid over the square.
    TriangleMesh needle = make_mesh(
        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {-1e-11 / std::sqrt(2.0), 1 + 1e-11 / std::sqrt(2.0), 0}, {0, 0, -1}},
        {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
    ASSERT_EQ(validate(needle).zero_area_faces, 1);
    EXPECT_THROW((void)convert(needle), InvalidMeshError);
    RepairReport report;
    const TriangleMesh repaired = repair(needle, {}, &report);
    EXPECT_EQ(report.collapsed_needles, 1);
    EXPECT_EQ(report.merged_vertices, 0);
    EXPECT_EQ(report.dropped_repeated_index_faces, 2);
    // The square's two faces and the pyramid's four: 2 + 4·√3/2.
    const MeshInfo info = expect_mended(repaired, 6, 2 + 2 * std::sqrt(3.0), 1e-10);
    EXPECT_EQ(info.euler_characteristic, 2);
    EXPECT_EQ(info.orientation_conflicts, 0);
    EXPECT_EQ(repaired.V.row(2), Eigen::RowVector3d(0, 1, 0));  // the smaller index stays where it was
    EXPECT_TRUE(convert(repaired).report.certificate.self_delaunay);
    expect_repairs_to_itself(repaired);

    // Kept on request.
    RepairOptions keep;
    keep.collapse_needles = false;
    EXPECT_EQ(validate(repair(needle, keep, &report)).zero_area_faces, 1);
    EXPECT_EQ(report.collapsed_needles, 0);
}

// A fan of caps: n + 1 collinear vertices p0..pn on the x axis, each pair p_i p_i+1 joined to pn
// by a cap, so that each cap's long side p_i-pn is the next cap's short side. Below, a fan of
// real faces to (0.5, -1); above, one face p0-pn-(0.5, 1). Each flip mends one cap and leaves
// the next one's long side facing a real face (cura's deltacomb_dc20.stl has a chain of 17).
TriangleMesh fan_of_caps(int n, bool with_top) {
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i <= n; ++i) points.emplace_back(static_cast<double>(i) / n, 0, 0);
    const int below = n + 1, above = n + 2;
    points.emplace_back(0.5, -1, 0);
    points.emplace_back(0.5, 1, 0);
    std::vector<Eigen::Vector3i> faces;
    for (int i = 0; i < n; ++i) faces.emplace_back(i + 1, i, below);
    for (int i = 0; i + 1 < n; ++i) faces.emplace_back(i, i + 1, n);  // the caps
    if (with_top) faces.emplace_back(0, n, above);
    TriangleMesh mesh;
    mesh.V.resize(static_cast<int>(points.size()), 3);
    for (size_t v = 0; v < points.size(); ++v) mesh.V.row(static_cast<int>(v)) = points[v].transpose();
    mesh.F.resize(static_cast<int>(faces.size()), 3);
    for (size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<int>(f)) = faces[f].transpose();
    return mesh;
}

TEST(Repair, MendsAChainOfCapsInOneCall) {
    constexpr int n = 41;
    const TriangleMesh capped = fan_of_caps(n, true);
    ASSERT_EQ(validate(capped).zero_area_faces, n - 1);
    ASSERT_EQ(validate(capped).orientation_conflicts, 0);
    RepairReport report;
    const TriangleMesh repaired = repair(capped, {}, &report);
    EXPECT_EQ(report.flipped_caps, n - 1);
    MeshInfo info = validate(repaired);
    EXPECT_EQ(info.zero_area_faces, 0);
    EXPECT_EQ(info.faces, 2 * n);
    EXPECT_TRUE(info.manifold());
    EXPECT_EQ(info.orientation_conflicts, 0);
    EXPECT_EQ(info.boundary_loops, 1);
    EXPECT_NEAR(total_area(repaired), 1.0, 1e-14);  // each face of the top fan tiles part of p0-pn-top
    EXPECT_TRUE(convert(repaired).report.certificate.self_delaunay);
    expect_repairs_to_itself(repaired);

    // Without the top face, the first cap's long side is the boundary: the caps are dropped one
    // after the other, and p0..pn become the boundary.
    const TriangleMesh open = repair(fan_of_caps(n, false), {}, &report);
    EXPECT_EQ(report.dropped_caps, n - 1);
    info = validate(open);
    EXPECT_EQ(info.faces, n);
    EXPECT_EQ(info.zero_area_faces, 0);
    EXPECT_EQ(info.boundary_edges, n + 2);
    EXPECT_TRUE(info.manifold());
    EXPECT_NEAR(total_area(open), 0.5, 1e-15);
}

TEST(Repair, MergesTheEndsOfASideAsShortAsRounding) {
    // The octahedron with +x doubled 6e-16 away (as exporters round 0 to 5.7e-16), two faces
    // moved onto the copy, and two needles 0-4-6 and 5-0-6 closing the gap.
    TriangleMesh mesh = make_mesh(
        {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 6e-16, 0}},
        {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 6, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {6, 3, 5}, {0, 4, 6}, {5, 0, 6}});
    ASSERT_EQ(validate(mesh).zero_area_faces, 2);
    ASSERT_TRUE(validate(mesh).manifold());
    RepairReport report;
    const TriangleMesh repaired = repair(mesh, {}, &report);
    EXPECT_EQ(report.merged_vertices, 1);
    EXPECT_EQ(report.dropped_repeated_index_faces, 2);
    EXPECT_EQ(expect_mended(repaired, 8, 4 * std::sqrt(3.0), 1e-12).euler_characteristic, 2);
    EXPECT_EQ(repaired.V.row(0), Eigen::RowVector3d(1, 0, 0));  // the smaller index stays where it was
    // 1e-9 apart, the two are distinct vertices: nothing is merged.
    mesh.V(6, 1) = 1e-9;
    EXPECT_EQ(repair(mesh, {}, &report).num_faces(), 10);
    EXPECT_EQ(report.merged_vertices, 0);
}

TEST(Repair, DropsACapOnTheBoundary) {
    // The unit square with a vertex in the middle of its bottom side, and a cap 1-4-0 along that
    // side: its long side 0-1 is the boundary, its two others run along it.
    const TriangleMesh capped = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 0}},
                                          {{4, 1, 2}, {4, 2, 3}, {0, 4, 3}, {1, 4, 0}});
    ASSERT_EQ(validate(capped).zero_area_faces, 1);
    RepairReport report;
    const TriangleMesh repaired = repair(capped, {}, &report);
    EXPECT_EQ(report.dropped_caps, 1);
    EXPECT_EQ(report.flipped_caps, 0);
    const MeshInfo info = expect_mended(repaired, 3, 1.0, 1e-15);
    EXPECT_EQ(info.boundary_loops, 1);
    EXPECT_EQ(info.boundary_edges, 5);
    expect_repairs_to_itself(repaired);
    // A lone cap is a component of zero area: it goes, with its vertices.
    const TriangleMesh lone = repair(make_mesh({{0, 0, 0}, {2, 0, 0}, {1, 0, 0}}, {{0, 1, 2}}), {}, &report);
    EXPECT_EQ(lone.num_faces(), 0);
    EXPECT_EQ(lone.num_vertices(), 0);
}

TEST(Repair, DropsABoundaryCapWhoseApexIsOnTheBoundaryElsewhere) {
    // The unit square with a notch cut from the middle of its top side down to c = (0.5, 0), which
    // a cap 1-c-0 along the bottom side joins to both corners. Dropping the cap tears c's fan in
    // two: each half of the U gets its own copy of c.
    const TriangleMesh notched = make_mesh(
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 0}, {0.6, 1, 0}, {0.4, 1, 0}},
        {{4, 1, 2}, {4, 2, 5}, {4, 6, 3}, {4, 3, 0}, {1, 4, 0}});
    ASSERT_EQ(validate(notched).zero_area_faces, 1);
    ASSERT_TRUE(validate(notched).manifold());
    RepairReport report;
    const TriangleMesh repaired = repair(notched, {}, &report);
    EXPECT_EQ(report.dropped_caps, 1);
    EXPECT_EQ(report.split_vertices, 1);
    EXPECT_EQ(expect_mended(repaired, 4, 0.9, 1e-15).components, 2);  // the square less the notch
    EXPECT_TRUE(convert(repaired).report.certificate.self_delaunay);
    expect_repairs_to_itself(repaired);
    // Without the vertex split, the cap stays: dropping it would leave c non-manifold.
    RepairOptions keep;
    keep.split_nonmanifold_vertices = false;
    const MeshInfo kept = validate(repair(notched, keep, &report));
    EXPECT_EQ(kept.zero_area_faces, 1);
    EXPECT_TRUE(kept.manifold());
}

}  // namespace
}  // namespace sdmesh
