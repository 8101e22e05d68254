// Operators on meshes made in code and on the corpus: DEC identities, the Laplacian's properties,
// mass totals, Gauss–Bonnet, linear precision, the unit-sphere spectrum, determinism, the CLI.

#include <omp.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "cli_runner.hpp"
#include "matrix_market_reader.hpp"
#include "meshes.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/matrix_market.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/shapes.hpp"

namespace sdmesh {
namespace {

namespace fs = std::filesystem;
using Sparse = Eigen::SparseMatrix<double>;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;
constexpr MassType kMassTypes[] = {MassType::barycentric, MassType::circumcentric, MassType::mixed_voronoi,
                                   MassType::galerkin};

const char* name_of(MassType type) {
    switch (type) {
        case MassType::barycentric: return "barycentric";
        case MassType::circumcentric: return "circumcentric";
        case MassType::mixed_voronoi: return "mixed_voronoi";
        case MassType::galerkin: return "galerkin";
    }
    return "?";
}

// ---- meshes -----------------------------------------------------------------------------------

// A triangulation, with the mesh it came from (empty for a hand-built Δ-complex) and, for
// developable meshes, per-vertex functions that are linear in the surface's flat metric.
struct Fixture {
    TriangleMesh mesh;
    Triangulation t;
    Eigen::MatrixXd linear;
};

Fixture from_mesh(TriangleMesh mesh, Eigen::MatrixXd linear = {}) {
    Triangulation t = Triangulation::from_mesh(mesh);
    return {std::move(mesh), std::move(t), std::move(linear)};
}

// The square flat torus [0,1]² with vertex 0 at the corners and vertex 1 at the centre: four
// triangles (0, 0, 1), four edges joining 0 and 1 (parallel edges) and two self-loops at 0 (the
// square's sides). Right angles at the centre, so the sides have cotan weight 0 and the spokes 1.
Triangulation make_delta_torus() {
    Triangulation t;
    t.num_vertices = 2;
    t.F.resize(4, 3);
    t.F << 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1;
    t.E.resize(6, 2);
    t.E << 0, 0,  // e0: horizontal side, +x
        0, 0,     // e1: vertical side, +y
        0, 1,     // e2..e5: spokes from corners (0,0), (1,0), (1,1), (0,1) to the centre
        0, 1, 0, 1, 0, 1;
    // Faces: bottom (0,0)->(1,0)->c, right (1,0)->(1,1)->c, top (1,1)->(0,1)->c, left (0,1)->(0,0)->c.
    t.face_edge.resize(4, 3);
    t.face_edge << 3, 2, 0, 4, 3, 1, 5, 4, 0, 2, 5, 1;
    t.face_edge_sign.resize(4, 3);
    t.face_edge_sign << 1, -1, 1, 1, -1, 1, 1, -1, -1, 1, -1, -1;
    t.edge_halfedges.resize(6, 2);
    t.edge_halfedges << 2, 8, 5, 11, 1, 9, 0, 4, 3, 7, 6, 10;
    t.length.resize(6);
    t.length << 1, 1, std::sqrt(0.5), std::sqrt(0.5), std::sqrt(0.5), std::sqrt(0.5);
    t.check();
    return t;
}

struct Case {
    std::string name;
    std::function<Fixture()> make;
    bool developable = false;  ///< Fixture::linear is set
    bool has_positions = true; ///< Fixture::mesh is set (not for a hand-made Δ-complex)
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

Fixture with_linear(TriangleMesh mesh, Eigen::Index first, Eigen::Index count) {
    Eigen::MatrixXd linear = mesh.V.middleCols(first, count);
    return from_mesh(std::move(mesh), std::move(linear));
}

std::vector<Case> generated_cases() {
    return {
        {"icosphere1", [] { return from_mesh(make_icosphere(1)); }},
        {"icosphere3", [] { return from_mesh(make_icosphere(3)); }},
        {"grid", [] { return with_linear(make_grid(8, 6, 2.0, 1.0), 0, 2); }, true},
        {"skewed_grid", [] { return with_linear(make_grid(7, 5, 1.0, 1.0, 1.5), 0, 2); }, true},
        {"negative_dual_fan", [] { return with_linear(test::make_negative_dual_fan(), 0, 2); }, true},
        {"cylinder", [] { return with_linear(make_cylinder(16, 5, 1.0, 2.0), 2, 1); }, true},
        {"delta_torus", [] { return Fixture{{}, make_delta_torus(), {}}; }, false, false},
    };
}

// Manifold corpus meshes below 120k faces (read lazily; the list comes from MANIFEST.md).
std::vector<Case> corpus_cases() {
    std::vector<Case> cases;
    if (!test::corpus_available()) return cases;
    for (const auto& [file, row] : test::read_manifest()) {
        if (row[7] != "yes" || test::manifest_number(row[5]) >= 120000) continue;
        cases.push_back({file.substr(0, file.find('.')),
                         [file] { return from_mesh(read_mesh(test::corpus_dir() / file)); }});
    }
    return cases;
}

std::vector<Case> all_cases() {
    std::vector<Case> cases = generated_cases();
    for (Case& c : corpus_cases()) cases.push_back(std::move(c));
    return cases;
}

std::vector<Case> developable_cases() {
    std::vector<Case> cases;
    for (Case& c : generated_cases())
        if (c.developable) cases.push_back(std::move(c));
    return cases;
}

const Fixture& fixture(const Case& c) {
    static std::map<std::string, Fixture> cache;
    auto it = cache.find(c.name);
    if (it == cache.end()) it = cache.emplace(c.name, c.make()).first;
    return it->second;
}

// ---- helpers ----------------------------------------------------------------------------------

// Σ_i |A_ij| per column: the scale a column's rounding errors are relative to.
Eigen::VectorXd abs_column_sums(const Sparse& a) {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(a.cols());
    for (int j = 0; j < a.outerSize(); ++j)
        for (Sparse::InnerIterator it(a, j); it; ++it) sum[j] += std::abs(it.value());
    return sum;
}

// Every entry of a - b is within tolerance · (the column's scale in a and b).
void expect_close(const Sparse& a, const Sparse& b, double tolerance, const std::string& what) {
    ASSERT_EQ(a.rows(), b.rows()) << what;
    ASSERT_EQ(a.cols(), b.cols()) << what;
    const Eigen::VectorXd scale = abs_column_sums(a) + abs_column_sums(b);
    const Sparse difference = a - b;
    int reported = 0;
    for (int j = 0; j < difference.outerSize(); ++j)
        for (Sparse::InnerIterator it(difference, j); it; ++it)
            if (std::abs(it.value()) > tolerance * scale[j] && reported++ < 5)
                ADD_FAILURE() << what << ": entry (" << it.row() << ", " << j << ") differs by " << it.value()
                              << ", column scale " << scale[j];
}

void expect_structure(const Sparse& a, const std::string& what) {
    EXPECT_TRUE(a.isCompressed()) << what;
    for (int j = 0; j < a.outerSize(); ++j)
        for (int i = a.outerIndexPtr()[j] + 1; i < a.outerIndexPtr()[j + 1]; ++i)
            ASSERT_LT(a.innerIndexPtr()[i - 1], a.innerIndexPtr()[i]) << what << ": column " << j << " not sorted";
}

double entry_sum(const Sparse& a) { return Eigen::VectorXd(a.coeffs()).sum(); }
double abs_entry_sum(const Sparse& a) { return a.coeffs().cwiseAbs().sum(); }
double max_abs(const Sparse& a) { return a.nonZeros() > 0 ? a.coeffs().cwiseAbs().maxCoeff() : 0.0; }

// Vertices on a boundary edge.
std::vector<bool> boundary_vertices(const Triangulation& t) {
    std::vector<bool> boundary(t.num_vertices, false);
    for (int e = 0; e < t.num_edges(); ++e)
        if (t.is_boundary(e)) boundary[t.E(e, 0)] = boundary[t.E(e, 1)] = true;
    return boundary;
}

// ---- identities on every mesh ------------------------------------------------------------------

class Operators : public ::testing::TestWithParam<Case> {};

TEST_P(Operators, ExteriorDerivativesComposeToZero) {
    const Triangulation& t = fixture(GetParam()).t;
    const Sparse D0 = d0(t), D1 = d1(t);
    EXPECT_EQ(D0.rows(), t.num_edges());
    EXPECT_EQ(D0.cols(), t.num_vertices);
    EXPECT_EQ(D1.rows(), t.num_faces());
    EXPECT_EQ(D1.cols(), t.num_edges());
    expect_structure(D0, "d0");
    expect_structure(D1, "d1");
    const Sparse product = D1 * D0;
    EXPECT_EQ(max_abs(product), 0.0);
    // d0 annihilates constants; a self-loop has an empty row.
    EXPECT_EQ((D0 * Eigen::VectorXd::Ones(t.num_vertices)).cwiseAbs().maxCoeff(), 0.0);
    int loops = 0;
    for (int e = 0; e < t.num_edges(); ++e) loops += t.E(e, 0) == t.E(e, 1);
    EXPECT_EQ(D0.nonZeros(), 2 * (t.num_edges() - loops));
}

TEST_P(Operators, LaplacianIsTheDecProduct) {
    const Triangulation& t = fixture(GetParam()).t;
    const Sparse L = cotan_laplacian(t);
    expect_structure(L, "L");
    const Sparse D0 = d0(t);
    const Sparse dec = Sparse(D0.transpose()) * star1(t).asDiagonal() * D0;
    expect_close(L, dec, 1e-12, "L - d0' star1 d0");
    // Pattern: the diagonal plus both directions of each pair of vertices joined by non-loop edges.
    std::set<std::pair<int, int>> pairs;
    for (int e = 0; e < t.num_edges(); ++e)
        if (t.E(e, 0) != t.E(e, 1)) pairs.emplace(t.E(e, 0), t.E(e, 1));
    EXPECT_EQ(L.nonZeros(), t.num_vertices + 2 * static_cast<Eigen::Index>(pairs.size()));
    auto stored = [&L](int i, int j) {
        return std::binary_search(L.innerIndexPtr() + L.outerIndexPtr()[j], L.innerIndexPtr() + L.outerIndexPtr()[j + 1], i);
    };
    for (const auto& [i, j] : pairs) EXPECT_TRUE(stored(i, j) && stored(j, i)) << "edge " << i << ", " << j;
    for (int v = 0; v < t.num_vertices; ++v) EXPECT_TRUE(stored(v, v)) << "vertex " << v;
}

TEST_P(Operators, LaplacianIsSymmetricWithZeroRowSums) {
    const Triangulation& t = fixture(GetParam()).t;
    const Sparse L = cotan_laplacian(t);
    EXPECT_EQ(max_abs(L - Sparse(L.transpose())), 0.0);
    const Eigen::VectorXd row_sum = L * Eigen::VectorXd::Ones(t.num_vertices);
    const Eigen::VectorXd scale = abs_column_sums(L);
    for (int i = 0; i < t.num_vertices; ++i) EXPECT_LE(std::abs(row_sum[i]), 1e-14 * scale[i]) << "row " << i;
}

TEST_P(Operators, MassMatricesSumToTheArea) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.t;
    const double area = face_areas(t).sum();
    if (m.mesh.num_faces() > 0) {
        EXPECT_NEAR(area, test::total_area(m.mesh), 64 * t.num_faces() * kEps * area);
    }
    const Sparse barycentric = mass_matrix(t, MassType::barycentric);
    for (MassType type : kMassTypes) {
        const Sparse M = mass_matrix(t, type);
        expect_structure(M, name_of(type));
        EXPECT_EQ(M.rows(), t.num_vertices);
        EXPECT_EQ(M.cols(), t.num_vertices);
        EXPECT_NEAR(entry_sum(M), area, (t.num_vertices + 64) * kEps * abs_entry_sum(M)) << name_of(type);
        EXPECT_EQ(max_abs(M - Sparse(M.transpose())), 0.0) << name_of(type);
        if (type != MassType::galerkin) {
            EXPECT_EQ(M.nonZeros(), t.num_vertices) << name_of(type);
        }
        if (type != MassType::circumcentric) {
            EXPECT_GE(M.coeffs().minCoeff(), 0.0) << name_of(type);
        }
    }
    // Galerkin: the pattern of L, and its rows sum to the barycentric (row-sum lumped) mass.
    const Sparse galerkin = mass_matrix(t, MassType::galerkin), L = cotan_laplacian(t);
    EXPECT_TRUE(std::equal(L.outerIndexPtr(), L.outerIndexPtr() + L.cols() + 1, galerkin.outerIndexPtr()));
    EXPECT_TRUE(std::equal(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros(), galerkin.innerIndexPtr()));
    const Eigen::VectorXd lumped = galerkin * Eigen::VectorXd::Ones(t.num_vertices);
    for (int i = 0; i < t.num_vertices; ++i)
        EXPECT_NEAR(lumped[i], barycentric.coeff(i, i), 64 * kEps * barycentric.coeff(i, i)) << "vertex " << i;
    EXPECT_EQ(max_abs(mass_matrix(t, MassType::circumcentric) - diagonal_matrix(star0(t))), 0.0);
}

// Cases with positions, which the certificate needs.
class OperatorsWithPositions : public Operators {};

TEST_P(OperatorsWithPositions, Star0IsTheCertificatesDualArea) {
    const Fixture& m = fixture(GetParam());
    const Triangulation& t = m.t;
    const Eigen::VectorXd s0 = star0(t);
    const Eigen::VectorXd dual = certify(m.mesh).dual_area;
    // The certificate takes its lengths from positions with other arithmetic: they can differ from
    // t.length in the last bit, which a sliver's cotangent amplifies. Bound, per term l²·cot/8,
    // the change from relative length errors eps: δA/A <= eps·κ with κ = Σ l_i²|cot_i|/(2A)
    // (∂A/∂l_i = l_i·cot_i/2), and δcot <= eps·(Σ l_i²/(2A) + |cot|·κ).
    Eigen::VectorXd scale = Eigen::VectorXd::Zero(t.num_vertices);
    const Eigen::VectorXd area = face_areas(t);
    for (int f = 0; f < t.num_faces(); ++f) {
        double cot[3], l2[3], kappa = 0, sum_l2 = 0;
        for (int k = 0; k < 3; ++k) {
            cot[k] = corner_cotangent(t.side(f, k), t.side(f, (k + 1) % 3), t.side(f, (k + 2) % 3));
            l2[k] = t.side(f, k) * t.side(f, k);
            kappa += l2[k] * std::abs(cot[k]) / (2 * area[f]);
            sum_l2 += l2[k];
        }
        for (int k = 0; k < 3; ++k) {
            const double bound = l2[k] / 8 * (std::abs(cot[k]) * (1 + kappa) + sum_l2 / (2 * area[f]));
            scale[t.F(f, (k + 1) % 3)] += bound;
            scale[t.F(f, (k + 2) % 3)] += bound;
        }
    }
    for (int v = 0; v < t.num_vertices; ++v) EXPECT_NEAR(s0[v], dual[v], 8 * kEps * scale[v]) << "vertex " << v;
    const Eigen::VectorXd s2 = star2(t);
    EXPECT_EQ(s2.size(), t.num_faces());
    for (int f = 0; f < t.num_faces(); ++f) EXPECT_EQ(s2[f], 1 / area[f]);
}

TEST_P(OperatorsWithPositions, StarSignsFollowTheDelaunayCertificate) {
    const Fixture& m = fixture(GetParam());
    const DelaunayCertificate cert = certify(m.mesh, {.edge_margins = true});
    const Eigen::VectorXd s0 = star0(m.t), s1 = star1(m.t);
    // The sign of ⋆1 is the sign of the margin π - (α+β) (interior) or π/2 - α (boundary).
    for (int e = 0; e < m.t.num_edges(); ++e) {
        if (cert.edge_margin[e] > 1e-12) {
            EXPECT_GT(s1[e], 0.0) << "edge " << e;
        }
        if (cert.edge_margin[e] < -1e-12) {
            EXPECT_LT(s1[e], 0.0) << "edge " << e;
        }
    }
    if (cert.self_delaunay) {
        const double tolerance = 1e-12 * s1.cwiseAbs().maxCoeff();  // co-circular hinges have w = 0
        EXPECT_GE(s1.minCoeff(), -tolerance);
        EXPECT_GT(s0.minCoeff(), 0.0);
        EXPECT_NO_THROW(inverse_star(s0, "star0"));
        const Sparse L = cotan_laplacian(m.t);
        for (int j = 0; j < L.outerSize(); ++j)
            for (Sparse::InnerIterator it(L, j); it; ++it)
                if (it.row() != j) {
                    EXPECT_LE(it.value(), tolerance) << "L(" << it.row() << ", " << j << ")";
                }
    }
}

TEST_P(Operators, AngleDefectsSatisfyGaussBonnet) {
    const Triangulation& t = fixture(GetParam()).t;
    const Eigen::VectorXd defect = angle_defects(t);
    const int euler = t.num_vertices - t.num_edges() + t.num_faces();
    EXPECT_NEAR(defect.sum(), 2 * kPi * euler, 16 * kEps * 2 * kPi * (3 * t.num_faces() + t.num_vertices));
}

// In each face, the gradient of any function reproduces its differences along the two sides
// from corner 0, in the frame corner 0 = origin, corner 1 = (l2, 0), corner 2 = (x, y), y > 0.
TEST_P(Operators, GradientReproducesDifferencesAlongSides) {
    const Triangulation& t = fixture(GetParam()).t;
    const Sparse G = gradient(t);
    EXPECT_EQ(G.rows(), 2 * t.num_faces());
    EXPECT_EQ(G.cols(), t.num_vertices);
    expect_structure(G, "G");
    const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(t.num_vertices, -1.0, 2.0).array().sin();
    const Eigen::VectorXd g = G * u;
    for (int f = 0; f < t.num_faces(); ++f) {
        const double l0 = t.side(f, 0), l1 = t.side(f, 1), l2 = t.side(f, 2);
        const double x = (l1 * l1 + l2 * l2 - l0 * l0) / (2 * l2), y = std::sqrt(l1 * l1 - x * x);
        const double u0 = u[t.F(f, 0)], u1 = u[t.F(f, 1)], u2 = u[t.F(f, 2)];
        const double scale = (std::abs(g[2 * f]) + std::abs(g[2 * f + 1])) * (l0 + l1 + l2) + 1;
        EXPECT_NEAR(g[2 * f] * l2, u1 - u0, 1e-12 * scale) << "face " << f;
        EXPECT_NEAR(g[2 * f] * x + g[2 * f + 1] * y, u2 - u0, 1e-9 * scale) << "face " << f;
    }
}

TEST_P(Operators, DivergenceOfGradientIsMinusLaplacian) {
    const Triangulation& t = fixture(GetParam()).t;
    const Sparse div = divergence(t), G = gradient(t);
    EXPECT_EQ(div.rows(), t.num_vertices);
    EXPECT_EQ(div.cols(), 2 * t.num_faces());
    expect_structure(div, "div");
    expect_close(Sparse(-(div * G)), cotan_laplacian(t), 1e-12, "-div grad - L");
}

TEST_P(Operators, InverseStarsOfPositiveEntries) {
    const Triangulation& t = fixture(GetParam()).t;
    const Eigen::VectorXd s2 = star2(t);
    const Eigen::VectorXd inverse = inverse_star(s2, "star2");
    for (int f = 0; f < t.num_faces(); ++f) EXPECT_EQ(inverse[f], 1 / s2[f]);
    const Eigen::VectorXd s1 = star1(t);
    if (s1.minCoeff() <= 0) {
        EXPECT_THROW(inverse_star(s1, "star1"), NumericalError);
    }
}

std::vector<Case> positioned_cases() {
    std::vector<Case> cases;
    for (Case& c : all_cases())
        if (c.has_positions) cases.push_back(std::move(c));
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Meshes, Operators, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });
INSTANTIATE_TEST_SUITE_P(Meshes, OperatorsWithPositions, ::testing::ValuesIn(positioned_cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

TEST(Corpus, IsPresentForOperatorTests) {
    if (!test::corpus_available()) GTEST_SKIP() << "corpus not found at " << test::corpus_dir();
    EXPECT_GE(corpus_cases().size(), 8u);
}

// ---- developable meshes: linear functions --------------------------------------------------------

class LinearPrecision : public ::testing::TestWithParam<Case> {};

TEST_P(LinearPrecision, LaplacianKillsLinearFunctionsAtInteriorVertices) {
    const Fixture& m = fixture(GetParam());
    const Sparse L = cotan_laplacian(m.t);
    const Eigen::VectorXd scale = abs_column_sums(L);
    const std::vector<bool> boundary = boundary_vertices(m.t);
    for (int c = 0; c < m.linear.cols(); ++c) {
        const Eigen::VectorXd x = m.linear.col(c), Lx = L * x;
        const double size = x.cwiseAbs().maxCoeff();
        for (int v = 0; v < m.t.num_vertices; ++v)
            if (!boundary[v]) {
                EXPECT_NEAR(Lx[v], 0.0, 1e-13 * scale[v] * size) << "function " << c << ", vertex " << v;
            }
    }
}

TEST_P(LinearPrecision, GradientOfACoordinateHasUnitLength) {
    const Fixture& m = fixture(GetParam());
    const Eigen::VectorXd g = gradient(m.t) * m.linear.col(0);
    for (int f = 0; f < m.t.num_faces(); ++f)
        EXPECT_NEAR(std::hypot(g[2 * f], g[2 * f + 1]), 1.0, 1e-12) << "face " << f;
}

INSTANTIATE_TEST_SUITE_P(Developable, LinearPrecision, ::testing::ValuesIn(developable_cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

// ---- particular meshes -----------------------------------------------------------------------------

TEST(NonDelaunayMesh, NegativeDualCellIsComputedAndRefused) {
    const TriangleMesh fan = test::make_negative_dual_fan();
    const Triangulation t = Triangulation::from_mesh(fan);
    const Eigen::VectorXd s0 = star0(t);
    EXPECT_LT(s0[0], 0.0);
    EXPECT_NEAR(s0.sum(), test::total_area(fan), 1e-15);
    try {
        inverse_star(s0, "star0");
        ADD_FAILURE() << "no exception";
    } catch (const NumericalError& e) {
        EXPECT_NE(std::string(e.what()).find("star0: entry 0 is -"), std::string::npos) << e.what();
    }
    // The circumcentric mass keeps the sign; the other lumped masses stay positive.
    EXPECT_LT(mass_matrix(t, MassType::circumcentric).coeff(0, 0), 0.0);
    EXPECT_GT(mass_matrix(t, MassType::mixed_voronoi).coeff(0, 0), 0.0);
}

TEST(DeltaComplex, LoopsAndParallelEdgesOnTheFlatTorus) {
    const Triangulation t = make_delta_torus();
    const Eigen::MatrixXd L = Eigen::MatrixXd(cotan_laplacian(t));
    const double tol = 1e-14;
    EXPECT_NEAR(L(0, 0), 4, tol);
    EXPECT_NEAR(L(1, 1), 4, tol);
    EXPECT_NEAR(L(0, 1), -4, tol);
    EXPECT_NEAR(L(1, 0), -4, tol);
    EXPECT_EQ(cotan_laplacian(t).nonZeros(), 4);
    const Eigen::VectorXd s0 = star0(t), s1 = star1(t);
    EXPECT_NEAR(s0[0], 0.5, tol);
    EXPECT_NEAR(s0[1], 0.5, tol);
    EXPECT_NEAR(s1[0], 0.0, tol);
    EXPECT_NEAR(s1[2], 1.0, tol);
    const Eigen::MatrixXd galerkin = Eigen::MatrixXd(mass_matrix(t, MassType::galerkin));
    EXPECT_NEAR(galerkin(0, 0), 0.5, tol);  // 4 faces · (area/6 · 2 corners + 2 · area/12 of the loop)
    EXPECT_NEAR(galerkin(1, 1), 1.0 / 6, tol);
    EXPECT_NEAR(galerkin(0, 1), 1.0 / 6, tol);
    EXPECT_NEAR(mass_matrix(t, MassType::barycentric).coeff(0, 0), 2.0 / 3, tol);
    EXPECT_NEAR(mass_matrix(t, MassType::mixed_voronoi).coeff(1, 1), 0.5, tol);
    const Eigen::VectorXd defect = angle_defects(t);
    EXPECT_NEAR(defect[0], 0.0, 1e-14);
    EXPECT_NEAR(defect[1], 0.0, 1e-14);
    const Sparse D0 = d0(t);
    for (int v = 0; v < 2; ++v)
        for (Sparse::InnerIterator it(D0, v); it; ++it) EXPECT_GE(it.row(), 2) << "a self-loop's d0 row is empty";
}

TEST(EdgeCases, EmptyTriangulationGivesEmptyOperators) {
    Triangulation t;
    t.num_vertices = 3;
    EXPECT_EQ(cotan_laplacian(t).nonZeros(), 3);
    EXPECT_EQ(entry_sum(mass_matrix(t, MassType::galerkin)), 0.0);
    EXPECT_EQ(angle_defects(t), Eigen::VectorXd::Constant(3, 2 * kPi));
    EXPECT_EQ(d1(t).rows(), 0);
}

TEST(EdgeCases, RejectsInconsistentArrays) {
    Triangulation t = Triangulation::from_mesh(make_icosphere(0));
    t.length.resize(3);
    EXPECT_THROW(cotan_laplacian(t), InvalidMeshError);
    EXPECT_THROW(mass_matrix(t), InvalidMeshError);
    EXPECT_THROW(gradient(t), InvalidMeshError);
}

TEST(Scale, OperatorsScaleWithTheMesh) {
    for (const TriangleMesh& base : {make_icosphere(2), make_grid(6, 5, 1.0, 1.0, 1.7), make_cylinder(9, 3)}) {
        const Triangulation reference = Triangulation::from_mesh(base);
        for (double scale : {1e8, 1e-8}) {
            TriangleMesh scaled = base;
            scaled.V *= scale;
            const Triangulation t = Triangulation::from_mesh(scaled);
            const std::string what = "scale " + std::to_string(scale);
            expect_close(cotan_laplacian(t), cotan_laplacian(reference), 1e-13, "L, " + what);
            for (MassType type : kMassTypes)
                expect_close(Sparse(mass_matrix(t, type) / (scale * scale)), mass_matrix(reference, type), 1e-13,
                             std::string(name_of(type)) + ", " + what);
            expect_close(Sparse(gradient(t) * scale), gradient(reference), 1e-13, "G, " + what);
            EXPECT_TRUE(star2(t).isApprox(star2(reference) / (scale * scale), 1e-13)) << what;
            EXPECT_LE((angle_defects(t) - angle_defects(reference)).cwiseAbs().maxCoeff(), 1e-13) << what;
        }
    }
}

// ---- the unit sphere's spectrum ---------------------------------------------------------------------

// The 25 smallest eigenvalues of L φ = λ M φ with a lumped mass, ascending.
Eigen::VectorXd smallest_eigenvalues(const Triangulation& t, MassType mass) {
    const Eigen::MatrixXd L = Eigen::MatrixXd(cotan_laplacian(t)), M = Eigen::MatrixXd(mass_matrix(t, mass));
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(L, M, Eigen::EigenvaluesOnly);
    return solver.eigenvalues().head(25);
}

// Levels 1..3 (642 vertices); a dense solve at level 4 (2,562 vertices) takes 5-8 s.
TEST(SphereSpectrum, EigenvaluesAreLTimesLPlusOneWithMultiplicity) {
    for (MassType mass : {MassType::barycentric, MassType::circumcentric, MassType::mixed_voronoi}) {
        double previous_error = std::numeric_limits<double>::infinity();
        for (int level = 1; level <= 3; ++level) {
            const Triangulation t = Triangulation::from_mesh(make_icosphere(level));
            const double h = t.length.maxCoeff();
            const Eigen::VectorXd lambda = smallest_eigenvalues(t, mass);
            EXPECT_NEAR(lambda[0], 0.0, 1e-10);
            double error = 0;  // largest relative error over l = 1..4
            for (int l = 1; l <= 4; ++l) {
                const double exact = l * (l + 1);
                for (int i = l * l; i < (l + 1) * (l + 1); ++i) {
                    // The discretisation error is O(λ²h²); the icospheres show a constant of about
                    // 0.05, the bound leaves a factor 2.
                    EXPECT_NEAR(lambda[i], exact, 0.1 * exact * exact * h * h)
                        << name_of(mass) << ", level " << level << ", l = " << l << ", index " << i;
                    error = std::max(error, std::abs(lambda[i] - exact) / exact);
                }
                // The 2l+1 copies form a cluster, well below the next one.
                if (l < 4) {
                    EXPECT_LT(lambda[(l + 1) * (l + 1) - 1], lambda[(l + 1) * (l + 1)] - 1.0)
                        << name_of(mass) << ", level " << level << ", l = " << l;
                }
            }
            // Halving h should divide the error by about 4.
            EXPECT_LT(error, previous_error / 3) << name_of(mass) << ", level " << level;
            previous_error = error;
        }
    }
}

// ---- determinism -------------------------------------------------------------------------------------

template <class T>
bool same_bits(const T* a, const T* b, Eigen::Index n) {
    return std::memcmp(a, b, static_cast<size_t>(n) * sizeof(T)) == 0;
}

void expect_same_bits(const Sparse& a, const Sparse& b, const std::string& what) {
    ASSERT_EQ(a.nonZeros(), b.nonZeros()) << what;
    ASSERT_EQ(a.outerSize(), b.outerSize()) << what;
    EXPECT_TRUE(same_bits(a.outerIndexPtr(), b.outerIndexPtr(), a.outerSize() + 1)) << what;
    EXPECT_TRUE(same_bits(a.innerIndexPtr(), b.innerIndexPtr(), a.nonZeros())) << what;
    EXPECT_TRUE(same_bits(a.valuePtr(), b.valuePtr(), a.nonZeros())) << what;
}

void expect_same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    EXPECT_TRUE(same_bits(a.data(), b.data(), a.size())) << what;
}

TEST(Determinism, BitIdenticalForOneAndSeveralThreads) {
    const int initial = omp_get_max_threads();
    for (const TriangleMesh& mesh : {make_icosphere(5), make_grid(120, 90, 1.0, 1.0, 1.3)}) {
        const Triangulation t = Triangulation::from_mesh(mesh);
        omp_set_num_threads(1);
        const Sparse L1 = cotan_laplacian(t);
        std::vector<Sparse> M1;
        for (MassType type : kMassTypes) M1.push_back(mass_matrix(t, type));
        const Eigen::VectorXd s0 = star0(t), s1 = star1(t), k1 = angle_defects(t);
        for (int threads : {2, 3}) {
            omp_set_num_threads(threads);
            const std::string what = std::to_string(threads) + " threads";
            expect_same_bits(cotan_laplacian(t), L1, "L, " + what);
            for (size_t i = 0; i < M1.size(); ++i)
                expect_same_bits(mass_matrix(t, kMassTypes[i]), M1[i], std::string(name_of(kMassTypes[i])) + ", " + what);
            expect_same_bits(star0(t), s0, "star0, " + what);
            expect_same_bits(star1(t), s1, "star1, " + what);
            expect_same_bits(angle_defects(t), k1, "angle defects, " + what);
        }
    }
    omp_set_num_threads(initial);
}

// ---- Matrix Market files and the CLI ------------------------------------------------------------------

using test::parse_matrix_market;

using test::read_text;

class Files : public ::testing::Test {
protected:
    test::TemporaryFolder folder_{"sdmesh_operators"};
    const fs::path& dir_ = folder_.path();
};

TEST_F(Files, MatrixMarketRoundTripsExactly) {
    Sparse m(3, 4);
    m.insert(0, 0) = 1.0 / 3;
    m.insert(2, 1) = -1e-300;
    m.insert(1, 3) = 0.0;  // explicit zeros are written
    m.insert(2, 3) = 6.02214076e23;  // left uncompressed on purpose
    write_matrix_market(dir_ / "m.mtx", m);
    const std::string text = read_text(dir_ / "m.mtx");
    EXPECT_NE(text.find("\n3 4 4\n"), std::string::npos) << text;
    const Sparse back = parse_matrix_market(text);
    EXPECT_EQ(Eigen::MatrixXd(back), Eigen::MatrixXd(m));
    EXPECT_NE(text.find("2 4 0\n"), std::string::npos) << text;

    write_matrix_market(dir_ / "m.mtx.gz", m);
    gzFile gz = gzopen((dir_ / "m.mtx.gz").c_str(), "rb");
    ASSERT_NE(gz, nullptr);
    std::string unzipped(text.size() + 16, '\0');
    const int n = gzread(gz, unzipped.data(), static_cast<unsigned>(unzipped.size()));
    gzclose(gz);
    EXPECT_EQ(unzipped.substr(0, static_cast<size_t>(n)), text);
}

TEST_F(Files, MatrixMarketWriteFailureLeavesNothing) {
    EXPECT_THROW(write_matrix_market(dir_ / "missing" / "m.mtx", Sparse(2, 2)), IoError);
    EXPECT_TRUE(fs::is_empty(dir_));
}

using test::CliRun;
using test::run_cli;

TEST_F(Files, CliWritesOperatorsThatMatchTheLibrary) {
    const TriangleMesh mesh = make_icosphere(2);
    write_mesh(dir_ / "sphere.off", mesh);
    const fs::path out = dir_ / "out" / "sphere";  // created, parents included
    const CliRun r = run_cli("operators " + (dir_ / "sphere.off").string() + " --out " + out.string() + " --mass galerkin");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* file : {"L.mtx", "M.mtx", "d0.mtx", "d1.mtx", "star0.mtx", "star1.mtx", "star2.mtx", "report.json"})
        EXPECT_TRUE(fs::exists(out / file)) << file;
    const std::string report = read_text(out / "report.json");
    for (const char* key : {"vertices", "edges", "faces", "mass", "nnz_L", "nnz_M", "min_star0", "min_star1",
                            "negative_star0", "negative_star1", "seconds"})
        EXPECT_NE(report.find("\"" + std::string(key) + "\": "), std::string::npos) << key << "\n" << report;
    EXPECT_NE(report.find("\"mass\": \"galerkin\""), std::string::npos) << report;
    EXPECT_NE(report.find("\"negative_star0\": 0"), std::string::npos) << report;
    EXPECT_EQ(r.out, report);

    // The files give back the library's matrices exactly (17 significant digits).
    const Triangulation t = Triangulation::from_mesh(read_mesh(dir_ / "sphere.off"));
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read_text(out / "L.mtx"))), Eigen::MatrixXd(cotan_laplacian(t)));
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read_text(out / "M.mtx"))),
              Eigen::MatrixXd(mass_matrix(t, MassType::galerkin)));
    EXPECT_EQ(Eigen::MatrixXd(parse_matrix_market(read_text(out / "d1.mtx"))), Eigen::MatrixXd(d1(t)));
    EXPECT_EQ(Eigen::VectorXd(parse_matrix_market(read_text(out / "star0.mtx")).diagonal()), star0(t));
    EXPECT_EQ(parse_matrix_market(read_text(out / "star2.mtx")).nonZeros(), t.num_faces());
    for (const auto& entry : fs::directory_iterator(out))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(Files, CliReportsNegativeDualCells) {
    write_mesh(dir_ / "fan.obj", test::make_negative_dual_fan());
    const CliRun r = run_cli("operators " + (dir_ / "fan.obj").string() + " --out " + (dir_ / "fan").string() +
                              " --mass circumcentric");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out.find("\"negative_star0\": 0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"min_star0\": -"), std::string::npos) << r.out;
}

TEST_F(Files, CliRejectsBadArguments) {
    write_mesh(dir_ / "sphere.off", make_icosphere(0));
    const std::string mesh = (dir_ / "sphere.off").string();
    EXPECT_EQ(run_cli("operators " + mesh).code, 2);
    const CliRun bad_mass = run_cli("operators " + mesh + " --out " + (dir_ / "o").string() + " --mass lumpy");
    EXPECT_EQ(bad_mass.code, 2);
    EXPECT_NE(bad_mass.err.find("--mass"), std::string::npos) << bad_mass.err;
    const CliRun missing = run_cli("operators " + (dir_ / "none.obj").string() + " --out " + (dir_ / "o").string());
    EXPECT_EQ(missing.code, 3);
    EXPECT_FALSE(fs::exists(dir_ / "o"));
}

}  // namespace
}  // namespace sdmesh
