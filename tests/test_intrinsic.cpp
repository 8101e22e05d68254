// The intrinsic Delaunay triangulation: every interior edge locally Delaunay afterwards, a second
// run flips nothing, the metric (area, cone angles) is unchanged, already-Delaunay meshes are
// left alone, improper results are reported, and the CLI writes the same files as `operators`.

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "corpus.hpp"
#include "matrix_market_reader.hpp"
#include "meshes.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/shapes.hpp"

namespace sdmesh {
namespace {

namespace fs = std::filesystem;
using Sparse = Eigen::SparseMatrix<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// ---- meshes -----------------------------------------------------------------------------------

// Outward faces for four points in general position.
TriangleMesh tetrahedron(const Eigen::Matrix<double, 4, 3>& points) {
    TriangleMesh m;
    m.V = points;
    m.F.resize(4, 3);
    m.F << 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2;
    const Eigen::RowVector3d centre = m.V.colwise().mean();
    for (int f = 0; f < 4; ++f) {
        const Eigen::RowVector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
        if ((b - a).cross(c - a).dot((a + b + c) / 3 - centre) < 0) std::swap(m.F(f, 1), m.F(f, 2));
    }
    return m;
}

// Ye et al. 2020, Fig. 2 (ALGORITHMS.md §7): its iDT has a self-edge.
TriangleMesh improper_tetrahedron() {
    Eigen::Matrix<double, 4, 3> p;
    p << 0.005, 0, 0.130, 1.732, 1, 0, 1.732, -1, 0, -100, 0, 0;
    return tetrahedron(p);
}

// z += amplitude · sin(3x) cos(2y): a curved surface, so that the iDT is not a planar one.
TriangleMesh bumpy(TriangleMesh mesh, double amplitude) {
    for (int v = 0; v < mesh.num_vertices(); ++v)
        mesh.V(v, 2) += amplitude * std::sin(3 * mesh.V(v, 0)) * std::cos(2 * mesh.V(v, 1));
    return mesh;
}

// A grid whose middle row sits almost on the bottom one: angles near 180°, needle flips.
TriangleMesh cap_band() {
    TriangleMesh grid = make_grid(12, 2);
    for (int i = 0; i <= 12; ++i) grid.V(13 + i, 1) = 1e-3;
    return grid;
}

TriangleMesh scaled(TriangleMesh mesh, double factor) {
    mesh.V *= factor;
    return mesh;
}

struct Case {
    std::string name;
    std::function<TriangleMesh()> make;
    bool planar_convex = false;  ///< a planar mesh over a convex domain: iDT edges are straight
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<Case> generated_cases() {
    return {
        {"icosphere2", [] { return make_icosphere(2); }},
        {"grid", [] { return make_grid(8, 6, 2.0, 1.0); }, true},
        {"skewed_grid", [] { return make_grid(10, 8, 1.0, 1.0, 1.5); }, true},
        {"very_skewed_grid", [] { return make_grid(12, 10, 1.0, 1.0, 20.0); }, true},
        {"bumpy_skewed_grid", [] { return bumpy(make_grid(12, 10, 1.0, 1.0, 2.5), 0.05); }},
        {"cap_band", cap_band, true},
        {"tall_cylinder", [] { return make_cylinder(12, 2, 1.0, 8.0); }},
        {"flat_cylinder", [] { return make_cylinder(40, 6, 1.0, 0.1); }},
        {"negative_dual_fan", [] { return test::make_negative_dual_fan(); }},
        {"improper_tetrahedron", improper_tetrahedron},
        {"skewed_grid_x1e8", [] { return scaled(make_grid(10, 8, 1.0, 1.0, 1.5), 1e8); }, true},
        {"skewed_grid_x1em8", [] { return scaled(make_grid(10, 8, 1.0, 1.0, 1.5), 1e-8); }, true},
    };
}

// Manifold corpus meshes below 120k faces (read lazily; the list comes from MANIFEST.md).
std::vector<Case> corpus_cases() {
    std::vector<Case> cases;
    if (!test::corpus_available()) return cases;
    for (const auto& [file, row] : test::read_manifest()) {
        if (row[7] != "yes" || test::manifest_number(row[5]) >= 120000) continue;
        cases.push_back({file.substr(0, file.find('.')), [file] { return read_mesh(test::corpus_dir() / file); }});
    }
    return cases;
}

std::vector<Case> all_cases() {
    std::vector<Case> cases = generated_cases();
    for (Case& c : corpus_cases()) cases.push_back(std::move(c));
    return cases;
}

struct Fixture {
    TriangleMesh mesh;
    Triangulation input;
    IntrinsicResult idt;
};

const Fixture& fixture(const Case& c) {
    static std::map<std::string, Fixture> cache;
    auto it = cache.find(c.name);
    if (it == cache.end()) {
        Fixture f;
        f.mesh = c.make();
        f.input = Triangulation::from_mesh(f.mesh);
        f.idt = intrinsic_delaunay(f.input);
        it = cache.emplace(c.name, std::move(f)).first;
    }
    return it->second;
}

// ---- helpers ----------------------------------------------------------------------------------

// The lengths of the hinge of interior edge e: l, then (a, b) in the first face, (c, d) in the other.
std::array<double, 5> hinge(const Triangulation& t, int e) {
    const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
    const int f0 = h0 / 3, k0 = h0 % 3, f1 = h1 / 3, k1 = h1 % 3;
    return {t.length[e], t.side(f0, (k0 + 1) % 3), t.side(f0, (k0 + 2) % 3), t.side(f1, (k1 + 1) % 3),
            t.side(f1, (k1 + 2) % 3)};
}

double margin(const Triangulation& t, int e) {
    const auto [l, a, b, c, d] = hinge(t, e);
    return delaunay_margin(l, a, b, c, d);
}

double total_area(const Triangulation& t) { return face_areas(t).sum(); }

void expect_same_triangulation(const Triangulation& a, const Triangulation& b) {
    EXPECT_EQ(a.num_vertices, b.num_vertices);
    EXPECT_EQ(a.F, b.F);
    EXPECT_EQ(a.E, b.E);
    EXPECT_EQ(a.face_edge, b.face_edge);
    EXPECT_EQ(a.face_edge_sign, b.face_edge_sign);
    EXPECT_EQ(a.edge_halfedges, b.edge_halfedges);
    EXPECT_EQ(a.length, b.length);
}

// ---- properties on every mesh -----------------------------------------------------------------

class Intrinsic : public ::testing::TestWithParam<Case> {};

TEST_P(Intrinsic, ResultIsAConsistentDeltaComplex) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.idt.triangulation;
    EXPECT_NO_THROW(t.check());
    EXPECT_EQ(t.num_vertices, m.input.num_vertices);
    EXPECT_EQ(t.num_faces(), m.input.num_faces());
    EXPECT_EQ(t.num_edges(), m.input.num_edges());
    // Each interior edge is run along once in each direction (also a self-edge, by the sign
    // convention), so the orientation stays consistent and d1's rows sum to zero on it.
    Eigen::VectorXi sign_sum = Eigen::VectorXi::Zero(t.num_edges());
    for (int f = 0; f < t.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) sign_sum[t.face_edge(f, k)] += t.face_edge_sign(f, k);
    for (int e = 0; e < t.num_edges(); ++e) {
        EXPECT_LE(t.E(e, 0), t.E(e, 1));
        if (!t.is_boundary(e)) {
            EXPECT_EQ(sign_sum[e], 0) << "edge " << e;
        }
    }
    // Boundary edges are never flipped.
    for (int e = 0; e < t.num_edges(); ++e)
        if (m.input.is_boundary(e)) {
            EXPECT_TRUE(t.is_boundary(e));
            EXPECT_EQ(t.E.row(e), m.input.E.row(e));
            EXPECT_EQ(t.length[e], m.input.length[e]);
        }
}

// Re-certified from the output's lengths alone, and cross-checked with the square-root-free test
// wherever the margin is clear of rounding.
TEST_P(Intrinsic, EveryInteriorEdgeIsLocallyDelaunay) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.idt.triangulation;
    EXPECT_EQ(m.idt.report.status, "delaunay");
    for (int e = 0; e < t.num_edges(); ++e) {
        if (t.is_boundary(e)) continue;
        const double x = margin(t, e);
        ASSERT_GE(x, -kDelaunayTolerance) << "edge " << e;
        if (std::abs(x) > 1e-8) {
            const auto [l, a, b, c, d] = hinge(t, e);
            EXPECT_EQ(is_delaunay_sqrt_free(l, a, b, c, d), x > 0) << "edge " << e;
        }
    }
}

TEST_P(Intrinsic, SecondRunFlipsNothing) {
    const Fixture& m = fixture(GetParam());
    const IntrinsicResult again = intrinsic_delaunay(m.idt.triangulation);
    EXPECT_EQ(again.report.flips, 0);
    EXPECT_EQ(again.report.status, "delaunay");
    EXPECT_EQ(again.report.proper, m.idt.report.proper);
    expect_same_triangulation(again.triangulation, m.idt.triangulation);
}

TEST_P(Intrinsic, DeterministicResult) {
    const Fixture& m = fixture(GetParam());
    const IntrinsicResult again = intrinsic_delaunay(m.input);
    EXPECT_EQ(again.report.flips, m.idt.report.flips);
    expect_same_triangulation(again.triangulation, m.idt.triangulation);
}

// Flips change neither the surface's area nor any vertex's cone angle (so Gauss–Bonnet holds).
TEST_P(Intrinsic, AreaAndConeAnglesAreUnchanged) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.idt.triangulation;
    const double area = total_area(m.input);
    EXPECT_NEAR(total_area(t), area, 1e-12 * area);
    const Eigen::VectorXd before = angle_defects(m.input), after = angle_defects(t);
    // A cone angle is a sum of corner angles from rounded lengths: ~1e-16 per corner times the
    // valence, amplified by thin triangles (the corpus stays below 1e-13).
    for (int v = 0; v < t.num_vertices; ++v) EXPECT_NEAR(after[v], before[v], 1e-11) << "vertex " << v;
    const int euler = t.num_vertices - t.num_edges() + t.num_faces();
    EXPECT_NEAR(after.sum(), 2 * kPi * euler, 16 * kEps * 2 * kPi * (3 * t.num_faces() + t.num_vertices));
}

// A margin >= -tol means cot α + cot β = sin(α+β)/(sin α sin β) >= -tol/(sin α sin β), and
// 1/sin x <= 1 + |cot x|: that bounds how negative a cotan weight (and L_ij's sign) can be.
TEST_P(Intrinsic, CotanWeightsAreNonNegative) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.idt.triangulation;
    const Eigen::VectorXd w = star1(t);
    std::map<std::pair<int, int>, double> slack;  // per vertex pair joined only by interior edges
    std::map<std::pair<int, int>, bool> has_boundary;
    for (int e = 0; e < t.num_edges(); ++e) {
        const std::pair<int, int> ends(t.E(e, 0), t.E(e, 1));
        if (t.is_boundary(e)) {
            has_boundary[ends] = true;
            continue;
        }
        const auto [l, a, b, c, d] = hinge(t, e);
        const double bound = (kDelaunayTolerance + 64 * kEps) * (1 + std::abs(corner_cotangent(l, a, b))) *
                             (1 + std::abs(corner_cotangent(l, c, d))) / 2;
        EXPECT_GE(w[e], -bound) << "edge " << e;
        slack[ends] += bound;
    }
    const Sparse L = cotan_laplacian(t);
    for (int j = 0; j < L.outerSize(); ++j)
        for (Sparse::InnerIterator it(L, j); it; ++it) {
            const int i = static_cast<int>(it.row());
            if (i != j && !has_boundary[std::minmax(i, j)]) {
                EXPECT_LE(it.value(), slack[std::minmax(i, j)]) << i << ", " << j;
            }
        }
}

std::string case_name(const ::testing::TestParamInfo<Case>& param) { return param.param.name; }

INSTANTIATE_TEST_SUITE_P(Meshes, Intrinsic, ::testing::ValuesIn(all_cases()), case_name);

// On a planar mesh over a convex domain, intrinsic edges are straight segments: every new length
// is the distance between its endpoints' positions. Tests the flipped-length formula.
class PlanarIntrinsic : public ::testing::TestWithParam<Case> {};

TEST_P(PlanarIntrinsic, LengthsAreEuclidean) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.idt.triangulation;
    const double scale = bounding_box_diagonal(m.mesh);
    for (int e = 0; e < t.num_edges(); ++e) {
        ASSERT_NE(t.E(e, 0), t.E(e, 1));
        const double euclidean = (m.mesh.V.row(t.E(e, 1)) - m.mesh.V.row(t.E(e, 0))).norm();
        EXPECT_NEAR(t.length[e], euclidean, 1e-12 * scale) << "edge " << e;
    }
}

std::vector<Case> planar_cases() {
    std::vector<Case> cases;
    for (Case& c : generated_cases())
        if (c.planar_convex) cases.push_back(std::move(c));
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Meshes, PlanarIntrinsic, ::testing::ValuesIn(planar_cases()), case_name);

TEST(Intrinsic, CorpusIsPresent) {
    if (!test::corpus_available()) GTEST_SKIP() << "corpus not found at " << test::corpus_dir();
    EXPECT_GE(corpus_cases().size(), 8u);
}

// ---- specific cases ---------------------------------------------------------------------------

// See ConvertMethods.AFlatFanTakesLinearlyManyFlips: the same flips, by lengths alone.
TEST(Intrinsic, AFlatFanTakesLinearlyManyFlips) {
    constexpr int n = 8000;
    const IntrinsicResult result = intrinsic_delaunay(Triangulation::from_mesh(test::make_flat_fan(n)));
    EXPECT_EQ(result.report.status, "delaunay");
    EXPECT_LE(result.report.flips, 32 * n);  // n²/13 = 615 n
}

TEST(Intrinsic, SelfDelaunayMeshIsLeftAsItIs) {
    for (const TriangleMesh& mesh : {make_icosphere(1), make_icosphere(3), make_grid(8, 6, 2.0, 1.0)}) {
        ASSERT_TRUE(certify(mesh).self_delaunay);
        const Triangulation t = Triangulation::from_mesh(mesh);
        const IntrinsicResult idt = intrinsic_delaunay(t);
        EXPECT_EQ(idt.report.flips, 0);
        EXPECT_TRUE(idt.report.proper);
        expect_same_triangulation(idt.triangulation, t);
        EXPECT_EQ(Eigen::MatrixXd(cotan_laplacian(idt.triangulation)), Eigen::MatrixXd(cotan_laplacian(t)));
    }
}

// The conversion's output is self-Delaunay, so it is its own iDT: L on its extrinsic connectivity
// is L of its iDT.
TEST(Intrinsic, ConversionOutputIsItsOwnIntrinsicDelaunayTriangulation) {
    const TriangleMesh bunny = read_mesh(std::string(SDMESH_TEST_DATA_DIR) + "/bunny.obj");
    for (const TriangleMesh& mesh : {bunny, bumpy(make_grid(12, 10, 1.0, 1.0, 2.5), 0.05)}) {
        const Triangulation before = Triangulation::from_mesh(mesh);
        EXPECT_GT(intrinsic_delaunay(before).report.flips, 0);
        const ConversionResult converted = convert(mesh);
        ASSERT_EQ(converted.report.status, ConvertStatus::certified);
        const Triangulation t = Triangulation::from_mesh(converted.mesh);
        const IntrinsicResult idt = intrinsic_delaunay(t);
        EXPECT_EQ(idt.report.flips, 0);
        EXPECT_TRUE(idt.report.proper);
        expect_same_triangulation(idt.triangulation, t);
        EXPECT_EQ(Eigen::MatrixXd(cotan_laplacian(idt.triangulation)), Eigen::MatrixXd(cotan_laplacian(t)));
    }
}

TEST(Intrinsic, ImproperTetrahedronIsReported) {
    const IntrinsicResult idt = intrinsic_delaunay(Triangulation::from_mesh(improper_tetrahedron()));
    const IntrinsicReport& r = idt.report;
    EXPECT_GT(r.flips, 0);
    EXPECT_FALSE(r.proper);
    EXPECT_GE(r.self_edges, 1);
    EXPECT_EQ(r.status, "delaunay");
    int loops = 0;
    std::map<std::pair<int, int>, int> pairs;
    for (int e = 0; e < idt.triangulation.num_edges(); ++e) {
        loops += idt.triangulation.E(e, 0) == idt.triangulation.E(e, 1);
        ++pairs[{idt.triangulation.E(e, 0), idt.triangulation.E(e, 1)}];
    }
    EXPECT_EQ(r.self_edges, loops);
    int repeated = 0;
    for (const auto& [ends, count] : pairs)
        if (ends.first != ends.second) repeated += count - 1;
    EXPECT_EQ(r.repeated_edges, repeated);
    // The operators accept the Δ-complex: L is symmetric with zero row sums, M sums to the area.
    const Sparse L = cotan_laplacian(idt.triangulation);
    EXPECT_LT((Eigen::MatrixXd(L) - Eigen::MatrixXd(L).transpose()).norm(), 1e-12);
    EXPECT_LT((L * Eigen::VectorXd::Ones(4)).norm(), 1e-12 * Eigen::MatrixXd(L).cwiseAbs().sum());
    const double area = total_area(idt.triangulation);
    EXPECT_NEAR(Eigen::MatrixXd(mass_matrix(idt.triangulation, MassType::galerkin)).sum(), area, 1e-12 * area);
}

// A hinge p, q, r, s with q ~1.8e8 away from p, r and s: the flip is needed (margin -2e-8) and
// leaves an angle of π - 3e-8 at p, where the computed |rs| rounds onto |rp| + |ps|. The flip
// must still give a triangle of positive area, |rs| a few ulps below that sum.
TEST(Intrinsic, NearlyStraightFlipStaysATriangle) {
    // Found by a random search; hexadecimal so that the bits are exact.
    const double l = 0x1.5ae147ae147aep+27, a = 0x1.24189374bc6a8p+0, b = l, c = 0x1.1e353f7ced916p+0,
                 d = std::nextafter(l, 0.0);
    Eigen::MatrixX3i F(2, 3);
    F << 2, 0, 1, 3, 1, 0;  // (r, p, q) and (s, q, p)
    Eigen::MatrixX3d side(2, 3);
    side << l, b, a, l, c, d;
    const Triangulation t = Triangulation::from_side_lengths(F, side, 4);
    const IntrinsicResult idt = intrinsic_delaunay(t);
    ASSERT_EQ(idt.report.flips, 1);
    EXPECT_NO_THROW(idt.triangulation.check());
    const int rs = t.face_edge(0, 0);  // the flipped edge keeps its id
    EXPECT_EQ(idt.triangulation.E.row(rs), Eigen::RowVector2i(2, 3));
    EXPECT_LT(idt.triangulation.length[rs], a + c);
    EXPECT_NEAR(idt.triangulation.length[rs], a + c, 64 * kEps * (a + c));
    EXPECT_NEAR(total_area(idt.triangulation), total_area(t), 1e-12 * total_area(t));
}

// A hinge flat within rounding, from an unseen mesh (speaker3.obj): both faces have an angle
// within ~1e-8 of π, at r and at p, so the four vertices lie nearly on a line. It is not LD
// (margin below -1e-10), but no length of rs keeps both new faces inside the triangle
// inequality: the flip made a face of zero area, whose cotangents came out infinite. The edge
// stays, counted, and the status says so.
TEST(Intrinsic, AHingeFlatWithinRoundingIsLeftUnflipped) {
    const double l = 28.596145000000281, a = 22.921585000000196, b = 5.6745600000000875, c = 3.9796110000001241,
                 d = 32.575756000000382;
    Eigen::MatrixX3i F(2, 3);
    F << 2, 0, 1, 3, 1, 0;  // (r, p, q) and (s, q, p)
    Eigen::MatrixX3d side(2, 3);
    side << l, b, a, l, c, d;
    const Triangulation t = Triangulation::from_side_lengths(F, side, 4);
    ASSERT_LT(delaunay_margin(l, a, b, c, d), -kDelaunayTolerance);
    const IntrinsicResult idt = intrinsic_delaunay(t);
    EXPECT_EQ(idt.report.flips, 0);
    EXPECT_EQ(idt.report.unflippable_edges, 1);
    EXPECT_EQ(idt.report.status, "unflippable_edges");
    EXPECT_NO_THROW(idt.triangulation.check());
    EXPECT_TRUE(cotan_laplacian(idt.triangulation).coeffs().allFinite());
}

TEST(Intrinsic, ProperIsTrueOnOrdinaryMeshes) {
    const IntrinsicResult idt = intrinsic_delaunay(Triangulation::from_mesh(make_grid(10, 8, 1.0, 1.0, 1.5)));
    EXPECT_GT(idt.report.flips, 0);
    EXPECT_TRUE(idt.report.proper);
    EXPECT_EQ(idt.report.self_edges, 0);
    EXPECT_EQ(idt.report.repeated_edges, 0);
    EXPECT_GE(idt.report.flip_seconds, 0);
    EXPECT_GE(idt.report.seconds, idt.report.flip_seconds);
}

// Scaling by a power of two is exact in every formula: same flips, lengths scaled exactly. Far
// from 1 too: flips run at a unit mean length (at 2^450 the LD test's products of four lengths
// had overflowed: the bunny made 1.55 million flips instead of 240; at 2^-460, none).
TEST(Intrinsic, PowerOfTwoScalingIsExact) {
    const TriangleMesh mesh = bumpy(make_grid(12, 10, 1.0, 1.0, 2.5), 0.05);
    const IntrinsicResult reference = intrinsic_delaunay(Triangulation::from_mesh(mesh));
    ASSERT_GT(reference.report.flips, 0);
    for (const double factor : {0x1p-460, 0x1p-40, 0x1p40, 0x1p450}) {
        const IntrinsicResult idt = intrinsic_delaunay(Triangulation::from_mesh(scaled(mesh, factor)));
        EXPECT_EQ(idt.report.flips, reference.report.flips);
        EXPECT_EQ(idt.triangulation.F, reference.triangulation.F);
        EXPECT_EQ(idt.triangulation.length, reference.triangulation.length * factor);
    }
}

TEST(Intrinsic, FlipBudgetBecomesAStatus) {
    const Triangulation t = Triangulation::from_mesh(make_grid(10, 8, 1.0, 1.0, 1.5));
    const long long needed = intrinsic_delaunay(t).report.flips;
    ASSERT_GT(needed, 3);
    for (const long long budget : {0LL, 3LL}) {
        const IntrinsicResult partial = intrinsic_delaunay(t, {.max_flips = budget});
        EXPECT_EQ(partial.report.flips, budget);
        EXPECT_EQ(partial.report.status, "flip_budget_exhausted");
        EXPECT_NO_THROW(partial.triangulation.check());
        // Finishing from there gives an iDT.
        const IntrinsicResult rest = intrinsic_delaunay(partial.triangulation);
        EXPECT_EQ(rest.report.status, "delaunay");
        for (int e = 0; e < t.num_edges(); ++e) {
            if (!rest.triangulation.is_boundary(e)) {
                EXPECT_GE(margin(rest.triangulation, e), -kDelaunayTolerance);
            }
        }
    }
    const IntrinsicResult exact = intrinsic_delaunay(t, {.max_flips = needed});
    EXPECT_EQ(exact.report.status, "delaunay");
}

TEST(Intrinsic, LargerToleranceFlipsLess) {
    const Triangulation t = Triangulation::from_mesh(bumpy(make_grid(12, 10, 1.0, 1.0, 2.5), 0.05));
    const IntrinsicResult strict = intrinsic_delaunay(t, {.tolerance = 0});
    const IntrinsicResult loose = intrinsic_delaunay(t, {.tolerance = 0.5});
    EXPECT_LT(loose.report.flips, strict.report.flips);
    for (int e = 0; e < t.num_edges(); ++e) {
        if (!t.is_boundary(e)) {
            EXPECT_GE(margin(loose.triangulation, e), -0.5);
        }
    }
}

TEST(Intrinsic, RejectsInvalidInput) {
    const Triangulation t = Triangulation::from_mesh(make_grid(3, 3));
    EXPECT_THROW(intrinsic_delaunay(t, {.tolerance = -1e-3}), InvalidArgumentError);
    EXPECT_THROW(intrinsic_delaunay(t, {.tolerance = std::numeric_limits<double>::quiet_NaN()}),
                 InvalidArgumentError);
    Triangulation bad_length = t;
    bad_length.length[0] = -1;
    EXPECT_THROW(intrinsic_delaunay(bad_length), InvalidMeshError);
    // Two faces running along their common edge in the same direction.
    TriangleMesh unoriented = make_grid(1, 1);
    std::swap(unoriented.F(1, 1), unoriented.F(1, 2));
    try {
        intrinsic_delaunay(Triangulation::from_mesh(unoriented));
        ADD_FAILURE() << "no exception";
    } catch (const InvalidMeshError& e) {
        EXPECT_NE(std::string(e.what()).find("oriented"), std::string::npos) << e.what();
    }
}

TEST(Intrinsic, EmptyTriangulation) {
    Triangulation t;
    t.num_vertices = 3;
    const IntrinsicResult idt = intrinsic_delaunay(t);
    EXPECT_EQ(idt.report.flips, 0);
    EXPECT_TRUE(idt.report.proper);
    EXPECT_EQ(idt.triangulation.num_vertices, 3);
}

// ---- the command line -------------------------------------------------------------------------

class Cli : public test::CliTest {
protected:
    [[nodiscard]] std::string out() const { return read(dir_ / "out.txt"); }
};

using test::parse_matrix_market;

TEST_F(Cli, WritesTheOperatorFilesOfTheIntrinsicTriangulation) {
    const std::string bunny = std::string(SDMESH_TEST_DATA_DIR) + "/bunny.obj";  // closed, not Delaunay
    const fs::path folder = dir_ / "out" / "bunny";  // created, parents included
    ASSERT_EQ(run("intrinsic " + bunny + " --out " + folder.string() + " --mass mixed"), 0) << read(dir_ / "err.txt");
    for (const char* file :
         {"L.mtx", "M.mtx", "d0.mtx", "d1.mtx", "star0.mtx", "star1.mtx", "star2.mtx", "report.json"})
        EXPECT_TRUE(fs::exists(folder / file)) << file;
    const std::string report = read(folder / "report.json");
    for (const char* key : {"file", "vertices", "edges", "faces", "mass", "nnz_L", "nnz_M", "min_star0", "min_star1",
                            "negative_star0", "negative_star1", "tolerance", "flips", "proper", "self_edges",
                            "repeated_edges", "status", "intrinsic_seconds", "flip_seconds", "seconds"})
        EXPECT_NE(report.find(std::string("\"") + key + "\": "), std::string::npos) << key << "\n" << report;
    EXPECT_NE(report.find("\"proper\": true"), std::string::npos) << report;
    EXPECT_NE(report.find("\"status\": \"delaunay\""), std::string::npos) << report;
    EXPECT_NE(report.find("\"negative_star1\": 0"), std::string::npos) << report;
    EXPECT_EQ(out(), report);

    const IntrinsicResult idt = intrinsic_delaunay(Triangulation::from_mesh(read_mesh(bunny)));
    EXPECT_NE(report.find("\"flips\": " + std::to_string(idt.report.flips) + ","), std::string::npos) << report;
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read(folder / "L.mtx"))),
              Eigen::MatrixXd(cotan_laplacian(idt.triangulation)));
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read(folder / "M.mtx"))),
              Eigen::MatrixXd(mass_matrix(idt.triangulation, MassType::mixed_voronoi)));
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read(folder / "d1.mtx"))), Eigen::MatrixXd(d1(idt.triangulation)));
}

TEST_F(Cli, ReportsAnImproperResultAndAnExhaustedBudget) {
    write_mesh(dir_ / "tet.obj", improper_tetrahedron());
    ASSERT_EQ(run("intrinsic " + (dir_ / "tet.obj").string() + " --out " + (dir_ / "tet").string()), 0);
    const std::string tet = out();
    EXPECT_NE(tet.find("\"proper\": false"), std::string::npos) << tet;
    EXPECT_NE(tet.find("\"self_edges\": 1"), std::string::npos) << tet;

    write_mesh(dir_ / "grid.obj", make_grid(10, 8, 1.0, 1.0, 1.5));
    const std::string grid = (dir_ / "grid.obj").string();
    // Out of its budget: the files are written, one line says so, and the exit code is 1.
    ASSERT_EQ(run("intrinsic " + grid + " --out " + (dir_ / "grid").string() + " --max-flips 2"), 1);
    const std::string budget = out();
    EXPECT_NE(budget.find("\"flips\": 2,"), std::string::npos) << budget;
    EXPECT_NE(budget.find("\"status\": \"flip_budget_exhausted\""), std::string::npos) << budget;
    EXPECT_TRUE(fs::exists(dir_ / "grid" / "L.mtx"));
    const std::string err = read(dir_ / "err.txt");
    EXPECT_EQ(err, "sdmesh intrinsic: " + grid +
                       ": the intrinsic flips ran out of their budget after 2 flips: the triangulation is not "
                       "Delaunay (--max-flips sets the budget)\n");
}

TEST_F(Cli, RejectsBadArguments) {
    write_mesh(dir_ / "sphere.off", make_icosphere(0));
    const std::string mesh = (dir_ / "sphere.off").string(), folder = " --out " + (dir_ / "o").string();
    EXPECT_EQ(run("intrinsic " + mesh), 2);
    EXPECT_EQ(run("intrinsic " + mesh + folder + " --mass lumpy"), 2);
    EXPECT_EQ(run("intrinsic " + mesh + folder + " --max-flips -1"), 2);
    EXPECT_EQ(run("intrinsic " + mesh + folder + " --max-flips 2.5"), 2);
    EXPECT_EQ(run("intrinsic " + mesh + folder + " --tolerance -1"), 7);
    EXPECT_EQ(run("intrinsic " + (dir_ / "none.obj").string() + folder), 3);
    EXPECT_FALSE(fs::exists(dir_ / "o"));
}

}  // namespace
}  // namespace sdmesh
