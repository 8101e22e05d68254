// Closest points (triangle and AABB tree) and the sampled Hausdorff distance.

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "meshes.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/shapes.hpp"

namespace sdmesh {
namespace {

using Eigen::Vector3d;
using test::make_mesh;
constexpr double kEps = std::numeric_limits<double>::epsilon();

Vector3d corner(const TriangleMesh& mesh, int f, int k) { return mesh.V.row(mesh.F(f, k)).transpose(); }

// ---- One triangle -------------------------------------------------------------------------------

void expect_closest(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                    const Vector3d& expected) {
    const Vector3d x = closest_point_on_triangle(p, a, b, c);
    EXPECT_LE((x - expected).norm(), 4 * kEps) << "query " << p.transpose() << " gave " << x.transpose();
}

// Right triangle in the z = 0 plane: one query in each of its seven Voronoi regions.
TEST(TriangleClosestPoint, EachVoronoiRegion) {
    const Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    expect_closest({-1, -1, 0.5}, a, b, c, a);
    expect_closest({2, -0.5, 1}, a, b, c, b);
    expect_closest({-0.5, 2, -1}, a, b, c, c);
    expect_closest({0.3, -2, 1}, a, b, c, {0.3, 0, 0});    // edge ab
    expect_closest({-3, 0.4, 0}, a, b, c, {0, 0.4, 0});    // edge ca
    expect_closest({1, 1, 0.5}, a, b, c, {0.5, 0.5, 0});   // edge bc
    expect_closest({0.2, 0.3, -0.7}, a, b, c, {0.2, 0.3, 0});  // interior
    // Vertices are returned exactly.
    EXPECT_EQ(closest_point_on_triangle({-1, -1, 0.5}, a, b, c), a);
    EXPECT_EQ(closest_point_on_triangle({2, -0.5, 1}, a, b, c), b);
}

// Obtuse at a: the query is beyond both lines ab and ca, and the answer is inside edge ca, not
// at the shared vertex: c + 14/17 (a - c) = (-12/17, 3/17, 0).
TEST(TriangleClosestPoint, BeyondTwoEdgesOfAnObtuseTriangle) {
    const Vector3d a(0, 0, 0), b(4, 0, 0), c(-4, 1, 0);
    expect_closest({-1, -1, 0}, a, b, c, {-12.0 / 17, 3.0 / 17, 0});
    expect_closest({-1, -1, 2}, a, b, c, {-12.0 / 17, 3.0 / 17, 0});
}

TEST(TriangleClosestPoint, DegenerateTrianglesGiveTheirEdges) {
    // Collinear, c beyond b.
    const Vector3d o(0, 0, 0), x1(1, 0, 0), x3(3, 0, 0);
    expect_closest({2, 1, 0}, o, x1, x3, {2, 0, 0});
    expect_closest({4, 0, 1}, o, x1, x3, x3);
    expect_closest({-1, 5, 0}, o, x1, x3, o);
    // Collinear, c between a and b.
    expect_closest({1, 0.5, 0}, o, {2, 0, 0}, x1, x1);
    // Two equal corners: a segment.
    expect_closest({1, 1, 0}, o, o, {0, 2, 0}, {0, 1, 0});
    // Three equal corners: a point.
    const Vector3d one(1, 1, 1);
    expect_closest({0, 0, 0}, one, one, one, one);
    // Needle of height 1e-12 (treated as its edges, which moves the answer by at most 1e-12).
    const Vector3d apex(0.5, 1e-12, 0);
    expect_closest({0.5, 0.5, 0.25}, o, x1, apex, apex);
    expect_closest({0.5, -0.5, 0}, o, x1, apex, {0.5, 0, 0});
    EXPECT_NEAR((closest_point_on_triangle({0.5, 5e-13, 3}, o, x1, apex) - Vector3d(0.5, 5e-13, 0)).norm(), 0, 1e-12);
    // A thin triangle above the threshold still projects onto its interior.
    expect_closest({0.5, 5e-7, 3}, o, x1, {0.5, 1e-6, 0}, {0.5, 5e-7, 0});
}

// ---- The tree against brute force -----------------------------------------------------------------

struct MeshCase {
    std::string name;
    TriangleMesh mesh;
};

void PrintTo(const MeshCase& c, std::ostream* os) { *os << c.name; }
std::string case_name(const ::testing::TestParamInfo<MeshCase>& info) { return info.param.name; }

ClosestPoint brute_force(const TriangleMesh& mesh, const Vector3d& q) {
    ClosestPoint best{std::numeric_limits<double>::infinity(), Vector3d::Zero(), -1};
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const Vector3d x = closest_point_on_triangle(q, corner(mesh, f, 0), corner(mesh, f, 1), corner(mesh, f, 2));
        if ((x - q).squaredNorm() < best.squared_distance) best = {(x - q).squaredNorm(), x, f};
    }
    return best;
}

// A planar grid with a repeated-index face and a zero-area face (collinear corners) added.
TriangleMesh grid_with_degenerate_faces() {
    TriangleMesh mesh = make_grid(6, 5, 1.0, 1.0, 0.7);
    mesh.F.conservativeResize(mesh.num_faces() + 2, 3);
    mesh.F.bottomRows(2) << 3, 3, 20,  //
        0, 1, 2;                       // first row of the grid: collinear
    mesh.V(20, 2) = 0.3;               // lift a vertex so the repeated face leaves the plane
    return mesh;
}

class TreeQueries : public ::testing::TestWithParam<MeshCase> {};

TEST_P(TreeQueries, MatchBruteForce) {
    const TriangleMesh& mesh = GetParam().mesh;
    const TriangleTree tree(mesh);
    EXPECT_EQ(tree.num_faces(), mesh.num_faces());
    const Eigen::AlignedBox3d box = tree.bounds();
    const Vector3d centre = box.center(), half = box.sizes() / 2 + Vector3d::Constant(0.1 * box.diagonal().norm());

    std::mt19937 rng(20240601);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::normal_distribution<double> jitter(0, 0.01 * box.diagonal().norm());
    for (int i = 0; i < 3000; ++i) {
        Vector3d q;
        if (i % 2 == 0) {  // anywhere around the mesh
            q = centre + half.cwiseProduct(Vector3d(unit(rng), unit(rng), unit(rng)));
        } else {  // close to the surface: a random point of a random face, moved a little
            const int f = static_cast<int>(rng() % static_cast<unsigned>(mesh.num_faces()));
            const double v = std::abs(unit(rng)), w = std::abs(unit(rng)) * (1 - v);
            q = corner(mesh, f, 0) + v * (corner(mesh, f, 1) - corner(mesh, f, 0)) +
                w * (corner(mesh, f, 2) - corner(mesh, f, 0)) + Vector3d(jitter(rng), jitter(rng), jitter(rng));
        }
        const ClosestPoint hit = tree.closest_point(q), expected = brute_force(mesh, q);
        ASSERT_GE(hit.face, 0);
        EXPECT_NEAR(std::sqrt(hit.squared_distance), std::sqrt(expected.squared_distance),
                    1e-12 * std::sqrt(expected.squared_distance))
            << "query " << q.transpose();
        EXPECT_EQ(hit.squared_distance, (hit.point - q).squaredNorm());
        EXPECT_EQ(hit.point, closest_point_on_triangle(q, corner(mesh, hit.face, 0), corner(mesh, hit.face, 1),
                                                       corner(mesh, hit.face, 2)));
        // From any face to start at: the same squared distance, bit for bit (what keeps the
        // Hausdorff samples deterministic), and a point of the face found.
        const int near_face = static_cast<int>(rng() % static_cast<unsigned>(mesh.num_faces()));
        const ClosestPoint from_near = tree.closest_point(q, near_face);
        EXPECT_EQ(from_near.squared_distance, hit.squared_distance) << "query " << q.transpose() << ", face " << near_face;
        EXPECT_EQ(from_near.point, closest_point_on_triangle(q, corner(mesh, from_near.face, 0),
                                                             corner(mesh, from_near.face, 1),
                                                             corner(mesh, from_near.face, 2)));
        EXPECT_EQ(tree.closest_point(q, hit.face).squared_distance, hit.squared_distance);
        // Within a radius: some face within it; beyond: the exact answer.
        for (const double radius2 : {0.0, 0.5 * hit.squared_distance, hit.squared_distance, 4 * hit.squared_distance}) {
            const ClosestPoint found = tree.closest_point_beyond(q, near_face, radius2);
            EXPECT_EQ(found.squared_distance, (found.point - q).squaredNorm());
            if (hit.squared_distance > radius2)
                EXPECT_EQ(found.squared_distance, hit.squared_distance) << "query " << q.transpose();
            else
                EXPECT_LE(found.squared_distance, radius2) << "query " << q.transpose();
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Meshes, TreeQueries,
                         ::testing::Values(MeshCase{"icosphere3", make_icosphere(3)},
                                           MeshCase{"skewed_grid", make_grid(12, 9, 2.0, 1.0, 1.5)},
                                           MeshCase{"cylinder", make_cylinder(24, 7, 0.5, 3.0)},
                                           MeshCase{"grid_with_degenerate_faces", grid_with_degenerate_faces()},
                                           MeshCase{"one_triangle", make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                                                              {{0, 1, 2}})}),
                         case_name);

TEST(TriangleTree, OutlivesItsMesh) {
    const TriangleTree tree(make_icosphere(2));
    const ClosestPoint hit = tree.closest_point({0, 0, 3});
    EXPECT_GT(hit.squared_distance, 1.9 * 1.9);
    EXPECT_LE(hit.squared_distance, 4.0);
}

TEST(TriangleTree, RejectsBadMeshes) {
    EXPECT_THROW(TriangleTree(TriangleMesh{}), InvalidMeshError);
    TriangleMesh mesh = make_icosphere(1);
    mesh.F(5, 1) = mesh.num_vertices();
    EXPECT_THROW(TriangleTree{mesh}, InvalidMeshError);
    mesh = make_icosphere(1);
    mesh.V(7, 2) = std::numeric_limits<double>::quiet_NaN();
    try {
        const TriangleTree tree(mesh);
        ADD_FAILURE() << "no exception for a NaN coordinate";
    } catch (const InvalidMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
    }
}

// ---- Hausdorff distance -------------------------------------------------------------------------

TEST(Hausdorff, IdenticalMeshesAreAtDistanceZero) {
    for (const TriangleMesh& mesh : {make_icosphere(3), make_grid(10, 7, 2.0, 1.0, 1.2), make_cylinder(16, 5)}) {
        const HausdorffReport r = hausdorff_distance(mesh, mesh);
        // Face samples are on the surface up to the rounding of a + v·ab + w·ac.
        EXPECT_LE(r.hausdorff, 8 * kEps * r.diagonal);
        EXPECT_LE(r.mean_forward, 8 * kEps * r.diagonal);
        EXPECT_DOUBLE_EQ(r.diagonal, bounding_box_diagonal(mesh));
    }
}

// Measured at the first mesh's unit diagonal by a power of two: the report scales exactly with
// both meshes. Unscaled, from coordinates of ~1e75 on the normals' squared norms overflowed,
// every face was taken for a sliver, and the distance grew 7-fold (bunny, decimated).
TEST(Hausdorff, TheUnitOfLengthOnlyScalesTheDistances) {
    const TriangleMesh a = make_icosphere(3);
    TriangleMesh b = a;
    b.V *= 1.01;
    const HausdorffReport reference = hausdorff_distance(a, b);
    for (const int exponent : {-480, 480}) {
        const HausdorffReport r =
            hausdorff_distance(scaled_by_power_of_two(a, exponent), scaled_by_power_of_two(b, exponent));
        EXPECT_EQ(r.hausdorff, std::ldexp(reference.hausdorff, exponent)) << exponent;
        EXPECT_EQ(r.mean_forward, std::ldexp(reference.mean_forward, exponent)) << exponent;
        EXPECT_EQ(r.hausdorff_rel, reference.hausdorff_rel) << exponent;
    }
}

// B = 1.01·A for a convex A inscribed in the unit sphere. Every point x of A has 1.01x on B (and
// every y of B has y/1.01 on A), so both one-sided distances are <= 0.01. Conversely a point of
// the convex A is at least min_f (1.01 d_f - n_f·x) >= 0.01 d_min from B, where d_f is the
// distance of face f's plane from the centre; likewise every point of B is >= 0.01 d_min from A.
// So every sample, hence also the maxima and the mean, lies in [0.01 d_min, 0.01].
TEST(Hausdorff, ScaledSphereIsAtOnePercent) {
    const TriangleMesh a = make_icosphere(3);
    TriangleMesh b = a;
    b.V *= 1.01;
    double d_min = 1;
    for (int f = 0; f < a.num_faces(); ++f) {
        const Vector3d n = (corner(a, f, 1) - corner(a, f, 0)).cross(corner(a, f, 2) - corner(a, f, 0)).normalized();
        d_min = std::min(d_min, n.dot(corner(a, f, 0)));
    }
    ASSERT_GT(d_min, 0.99);
    const double lo = 0.01 * d_min * (1 - 1e-9), hi = 0.01 * (1 + 1e-9);
    const HausdorffReport r = hausdorff_distance(a, b);
    for (double d : {r.forward, r.backward, r.mean_forward}) {
        EXPECT_GE(d, lo);
        EXPECT_LE(d, hi);
    }
    EXPECT_EQ(r.hausdorff, std::max(r.forward, r.backward));
    EXPECT_DOUBLE_EQ(r.diagonal, bounding_box_diagonal(a));
    EXPECT_EQ(r.hausdorff_rel, r.hausdorff / r.diagonal);
}

TEST(Hausdorff, LiftedGridIsExactlyTheLift) {
    const double h = 0.3;
    const TriangleMesh a = make_grid(10, 7, 2.0, 1.0, 0.8);
    TriangleMesh b = a;
    b.V.col(2).array() += h;
    const HausdorffReport r = hausdorff_distance(a, b);
    EXPECT_EQ(r.forward, h);
    EXPECT_EQ(r.backward, h);
    EXPECT_EQ(r.hausdorff, h);
    // Equal terms summed: k² = 16 per face, then over the faces (weights and total area).
    EXPECT_NEAR(r.mean_forward, h, (16 + 2 * a.num_faces()) * kEps * h);
}

// B keeps the faces of A with centroid x < 0.5 (and all of A's vertices, half unreferenced):
// B lies on A, and A's points at x = 1 are 0.5 from B.
TEST(Hausdorff, SubsetOfFaces) {
    const TriangleMesh a = make_grid(8, 6);
    TriangleMesh b = a;
    int kept = 0;
    for (int f = 0; f < a.num_faces(); ++f)
        if (corner(a, f, 0).x() + corner(a, f, 1).x() + corner(a, f, 2).x() < 1.5) b.F.row(kept++) = a.F.row(f);
    b.F.conservativeResize(kept, 3);
    ASSERT_EQ(kept, a.num_faces() / 2);
    const HausdorffReport r = hausdorff_distance(a, b);
    EXPECT_LE(r.backward, 8 * kEps);
    EXPECT_NEAR(r.forward, 0.5, 4 * kEps);
    EXPECT_EQ(r.hausdorff, r.forward);
    EXPECT_NEAR(r.hausdorff_rel, 0.5 / std::sqrt(2.0), 8 * kEps);
    EXPECT_GT(r.mean_forward, 0.1);
}

TEST(Hausdorff, SampleBudget) {
    const TriangleMesh mesh = make_icosphere(2);  // 162 vertices, 320 faces
    const long long nv = mesh.num_vertices(), nf = mesh.num_faces();
    EXPECT_EQ(hausdorff_distance(mesh, mesh).samples, 2 * (nv + nf * (16 + 3)));
    // 100 per face asks for k = 10; the budget allows k = 2.
    const long long budget = nv + nf * (4 + 3);
    EXPECT_EQ(hausdorff_distance(mesh, mesh, {.samples_per_face = 100, .max_samples = budget}).samples, 2 * budget);
    // Below k = 1 the minimal pattern is still taken.
    EXPECT_EQ(hausdorff_distance(mesh, mesh, {.max_samples = 1}).samples, 2 * (nv + nf * 4));
    EXPECT_THROW(hausdorff_distance(mesh, mesh, {.samples_per_face = 0}), InvalidArgumentError);
    EXPECT_THROW(hausdorff_distance(mesh, mesh, {.max_samples = 0}), InvalidArgumentError);
    EXPECT_THROW(hausdorff_distance(mesh, TriangleMesh{}), InvalidMeshError);
}

void expect_identical(const HausdorffReport& x, const HausdorffReport& y, const std::string& what) {
    EXPECT_EQ(x.forward, y.forward) << what;
    EXPECT_EQ(x.backward, y.backward) << what;
    EXPECT_EQ(x.hausdorff, y.hausdorff) << what;
    EXPECT_EQ(x.diagonal, y.diagonal) << what;
    EXPECT_EQ(x.hausdorff_rel, y.hausdorff_rel) << what;
    EXPECT_EQ(x.mean_forward, y.mean_forward) << what;
    EXPECT_EQ(x.samples, y.samples) << what;
}

TEST(Hausdorff, BitIdenticalAcrossRunsAndThreadCounts) {
    const TriangleMesh a = make_icosphere(4);
    TriangleMesh b = a;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> noise(-0.01, 0.01);
    for (Eigen::Index i = 0; i < b.V.size(); ++i) b.V.data()[i] += noise(rng);

    const int initial = omp_get_max_threads();
    omp_set_num_threads(1);
    const HausdorffReport serial = hausdorff_distance(a, b);
    expect_identical(hausdorff_distance(a, b), serial, "second run");
    for (int threads : {2, 3}) {
        omp_set_num_threads(threads);
        expect_identical(hausdorff_distance(a, b), serial, std::to_string(threads) + " threads");
    }
    omp_set_num_threads(initial);
    EXPECT_GT(serial.forward, 0);
}

// Without the mean, samples that cannot raise the maximum stop their search early: the same
// maxima to the bit, and on the shapes where the distance is set by few samples.
TEST(Hausdorff, WithoutTheMeanTheMaximaAreTheSame) {
    const TriangleMesh sphere = make_icosphere(4);
    TriangleMesh noisy = sphere, bumped = sphere;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> noise(-0.01, 0.01);
    for (Eigen::Index i = 0; i < noisy.V.size(); ++i) noisy.V.data()[i] += noise(rng);
    bumped.V.row(17) *= 1.3;  // one spike sets the distance
    const int initial = omp_get_max_threads();
    for (const auto& [name, b] : {std::pair{"noisy", &noisy}, std::pair{"bumped", &bumped}})
        for (int threads : {1, 2}) {
            omp_set_num_threads(threads);
            const HausdorffReport full = hausdorff_distance(sphere, *b);
            HausdorffReport maxima = hausdorff_distance(sphere, *b, {.mean = false});
            EXPECT_TRUE(std::isnan(maxima.mean_forward)) << name;
            maxima.mean_forward = full.mean_forward;
            expect_identical(maxima, full, std::string(name) + ", " + std::to_string(threads) + " threads");
            EXPECT_GT(full.forward, 0) << name;
        }
    omp_set_num_threads(initial);
    EXPECT_NEAR(hausdorff_distance(sphere, bumped, {.mean = false}).backward, 0.3, 1e-12);
}

// A sphere with a cap pushed out: the edit is measured on the cap's faces only, and gives the
// same distances as the whole measure, with the cap given as faces of A or as triangles.
TEST(HausdorffOfEdit, MeasuresOnlyTheChangedFacesAndAgreesWithTheWhole) {
    const TriangleMesh a = make_icosphere(3);
    TriangleMesh b = a;
    std::vector<char> moved_vertex(a.num_vertices(), 0);
    for (int v = 0; v < a.num_vertices(); ++v)
        if (a.V(v, 2) > 0.8) b.V.row(v) *= 1.05, moved_vertex[v] = 1;
    SurfaceEdit edit;
    edit.changed_faces.assign(b.num_faces(), 0);
    std::vector<int> cap;
    for (int f = 0; f < a.num_faces(); ++f)
        if (moved_vertex[a.F(f, 0)] || moved_vertex[a.F(f, 1)] || moved_vertex[a.F(f, 2)])
            edit.changed_faces[f] = 1, cap.push_back(f);
    ASSERT_GT(cap.size(), 10u);
    ASSERT_LT(cap.size(), a.num_faces() / 4);
    edit.replaced_faces = edit.changed_faces;  // b has a's faces

    const HausdorffReport whole = hausdorff_distance(a, b);
    const HausdorffReport by_faces = hausdorff_distance_of_edit(a, b, edit);
    EXPECT_EQ(by_faces.forward, whole.forward);
    EXPECT_EQ(by_faces.backward, whole.backward);
    EXPECT_EQ(by_faces.hausdorff_rel, whole.hausdorff_rel);
    EXPECT_NEAR(by_faces.mean_forward, whole.mean_forward, 1e-12);
    EXPECT_LT(by_faces.samples, whole.samples / 2);

    // The same cap as separate triangles of A: the faces they meet are found by distance.
    SurfaceEdit by_triangles{edit.changed_faces, {}, {}};
    by_triangles.replaced.V.resize(3 * static_cast<Eigen::Index>(cap.size()), 3);
    by_triangles.replaced.F.resize(static_cast<Eigen::Index>(cap.size()), 3);
    for (size_t t = 0; t < cap.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            by_triangles.replaced.V.row(3 * t + k) = a.V.row(a.F(cap[t], k));
            by_triangles.replaced.F(t, k) = static_cast<int>(3 * t + k);
        }
    const HausdorffReport by_distance = hausdorff_distance_of_edit(a, b, by_triangles);
    EXPECT_EQ(by_distance.hausdorff_rel, whole.hausdorff_rel);
    EXPECT_GE(by_distance.samples, by_faces.samples);  // the faces beside the cap too
    EXPECT_LT(by_distance.samples, whole.samples);

    // Nothing changed: nothing measured.
    const HausdorffReport none = hausdorff_distance_of_edit(a, a, {std::vector<char>(a.num_faces(), 0), {}, {}});
    EXPECT_EQ(none.hausdorff, 0.0);
    EXPECT_EQ(none.samples, 0);

    EXPECT_THROW(hausdorff_distance_of_edit(a, b, {std::vector<char>(3, 0), {}, {}}), InvalidArgumentError);
    EXPECT_THROW(hausdorff_distance_of_edit(a, b, {edit.changed_faces, std::vector<char>(3, 0), {}}),
                 InvalidArgumentError);
}

}  // namespace
}  // namespace sdmesh
