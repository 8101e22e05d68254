// Validation and certificate of every corpus mesh against the manifest and against a brute-force
// count written here independently (sorted edge list, acos angles).

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <tuple>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

struct BruteForce {
    int edges = 0, boundary_edges = 0, interior_edges = 0, nonmanifold_edges = 0;
    int nonmanifold_vertices = 0, boundary_loops = 0;
    int non_delaunay = 0;           // interior edges with α + β > π, acos angles
    int ambiguous = 0;              // interior edges with |α + β - π| < 1e-8
    int manifest_interior = 0;      // the manifest's definition: neither face degenerate
    int manifest_non_delaunay = 0;  // ... with α + β > π + 1e-12
};

double angle_at(const Eigen::Vector3d& apex, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double c = (a - apex).normalized().dot((b - apex).normalized());
    return std::acos(std::clamp(c, -1.0, 1.0));
}

BruteForce brute_force(const TriangleMesh& mesh) {
    const auto& V = mesh.V;
    const auto& F = mesh.F;
    const double diagonal = bounding_box_diagonal(mesh);
    std::vector<char> degenerate(F.rows());
    for (int f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
        degenerate[f] = 0.5 * (b - a).cross(c - a).norm() <= 1e-12 * diagonal * diagonal;
    }
    std::vector<std::tuple<int, int, int>> sides;  // (lo, hi, face)
    for (int f = 0; f < F.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int a = F(f, k), b = F(f, (k + 1) % 3);
            sides.emplace_back(std::min(a, b), std::max(a, b), f);
        }
    std::sort(sides.begin(), sides.end());

    BruteForce r;
    std::vector<std::vector<int>> vertex_faces(V.rows());
    for (int f = 0; f < F.rows(); ++f)
        for (int k = 0; k < 3; ++k) vertex_faces[F(f, k)].push_back(f);
    std::map<std::pair<int, int>, int> count;  // faces per edge
    std::vector<std::vector<int>> boundary_neighbours(V.rows());
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        while (j < sides.size() && std::get<0>(sides[j]) == std::get<0>(sides[i]) &&
               std::get<1>(sides[j]) == std::get<1>(sides[i]))
            ++j;
        const int p = std::get<0>(sides[i]), q = std::get<1>(sides[i]);
        const int n = static_cast<int>(j - i);
        count[{p, q}] = n;
        ++r.edges;
        if (n == 1) {
            ++r.boundary_edges;
            boundary_neighbours[p].push_back(q);
            boundary_neighbours[q].push_back(p);
        } else if (n > 2) {
            ++r.nonmanifold_edges;
        } else {
            ++r.interior_edges;
            const int f0 = std::get<2>(sides[i]), f1 = std::get<2>(sides[i + 1]);
            auto apex = [&](int f) {
                for (int k = 0; k < 3; ++k)
                    if (F(f, k) != p && F(f, k) != q) return F(f, k);
                return -1;
            };
            const Eigen::Vector3d P = V.row(p), Q = V.row(q);
            const double sum = angle_at(V.row(apex(f0)), P, Q) + angle_at(V.row(apex(f1)), P, Q);
            r.non_delaunay += sum > std::numbers::pi;
            r.ambiguous += std::abs(sum - std::numbers::pi) < 1e-8;
            if (!degenerate[f0] && !degenerate[f1]) {
                ++r.manifest_interior;
                r.manifest_non_delaunay += sum > std::numbers::pi + 1e-12;
            }
        }
        i = j;
    }
    // A vertex is non-manifold when its faces, joined where two of them share a neighbour w and
    // the edge (v, w) has exactly two faces, fall into more than one group.
    for (int v = 0; v < V.rows(); ++v) {
        const auto& faces = vertex_faces[v];
        std::vector<std::pair<int, int>> link;  // (neighbour w, index of the face in `faces`)
        for (size_t i = 0; i < faces.size(); ++i)
            for (int k = 0; k < 3; ++k)
                if (F(faces[i], k) != v) link.emplace_back(F(faces[i], k), static_cast<int>(i));
        std::sort(link.begin(), link.end());
        std::vector<int> group(faces.size());
        std::iota(group.begin(), group.end(), 0);
        auto root = [&group](int x) {
            while (group[x] != x) x = group[x];
            return x;
        };
        for (size_t i = 0; i + 1 < link.size(); ++i)
            if (link[i].first == link[i + 1].first &&
                count.at(std::minmax(v, link[i].first)) == 2)
                group[root(link[i].second)] = root(link[i + 1].second);
        int roots = 0;
        for (size_t i = 0; i < group.size(); ++i) roots += root(static_cast<int>(i)) == static_cast<int>(i);
        r.nonmanifold_vertices += roots > 1;
    }
    // Boundary loops: connected components of the boundary-edge graph (depth-first search).
    std::vector<char> seen(V.rows(), 0);
    for (int v = 0; v < V.rows(); ++v) {
        if (seen[v] || boundary_neighbours[v].empty()) continue;
        ++r.boundary_loops;
        std::vector<int> stack = {v};
        seen[v] = 1;
        while (!stack.empty()) {
            const int u = stack.back();
            stack.pop_back();
            for (int w : boundary_neighbours[u])
                if (!seen[w]) seen[w] = 1, stack.push_back(w);
        }
    }
    return r;
}

class CorpusMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(CorpusMesh, CountsMatchManifestAndBruteForce) {
    const std::string name = GetParam();
    const auto manifest = test::read_manifest();
    const auto& row = manifest.at(name);
    // First table: folder class source license #V #F closed/boundary manifold fraction;
    // second: file comps E χ genus ...
    const long long manifest_vertices = test::manifest_number(row[4]);
    const long long manifest_faces = test::manifest_number(row[5]);
    const double manifest_fraction = std::stod(row[8]);
    const long long manifest_components = test::manifest_number(row[10]);
    const long long manifest_edges = test::manifest_number(row[11]);
    const long long manifest_euler = test::manifest_number(row[12]);

    const TriangleMesh mesh = read_mesh(test::corpus_dir() / name);
    const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
    const MeshInfo info = validate(mesh, edges);
    const DelaunayCertificate cert = certify(mesh, edges);
    const BruteForce brute = brute_force(mesh);

    EXPECT_EQ(info.vertices, manifest_vertices);
    EXPECT_EQ(info.faces, manifest_faces);
    EXPECT_EQ(info.edges, manifest_edges);
    EXPECT_EQ(info.components, manifest_components);
    EXPECT_EQ(info.euler_characteristic, manifest_euler);
    EXPECT_EQ(info.genus, row[13].starts_with("n/a") ? -1 : test::manifest_number(row[13]));

    EXPECT_EQ(info.edges, brute.edges);
    EXPECT_EQ(info.boundary_edges, brute.boundary_edges);
    EXPECT_EQ(info.interior_edges, brute.interior_edges);
    EXPECT_EQ(info.nonmanifold_edges, brute.nonmanifold_edges);
    EXPECT_EQ(info.nonmanifold_vertices, brute.nonmanifold_vertices);
    EXPECT_EQ(info.boundary_loops, brute.boundary_loops);
    EXPECT_EQ(cert.interior_edges, brute.interior_edges);
    EXPECT_EQ(cert.boundary_edges, brute.boundary_edges);
    EXPECT_LE(std::abs(cert.non_delaunay_edges - brute.non_delaunay), brute.ambiguous);
    EXPECT_EQ(cert.self_delaunay, info.manifold() && brute.non_delaunay == 0 && cert.boundary_obtuse_edges == 0);

    // The manifest's fraction, rounded to 4 decimals, under its own definition.
    const double brute_fraction = double(brute.manifest_non_delaunay) / brute.manifest_interior;
    EXPECT_NEAR(brute_fraction, manifest_fraction, 1e-4);
    EXPECT_NEAR(double(cert.non_delaunay_edges) / cert.interior_edges, manifest_fraction,
                1e-4 + double(brute.interior_edges - brute.manifest_interior) / brute.interior_edges);
}

std::vector<std::string> corpus_names() {
    if (!test::corpus_available()) return {};
    std::vector<std::string> names;
    for (const auto& [name, row] : test::read_manifest()) names.push_back(name);
    return names;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    return info.param.substr(0, info.param.find('.'));
}

INSTANTIATE_TEST_SUITE_P(Manifest, CorpusMesh, ::testing::ValuesIn(corpus_names()), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(CorpusMesh);

TEST(Corpus, IsPresent) {
    if (!test::corpus_available()) GTEST_SKIP() << "corpus not found at " << test::corpus_dir();
    EXPECT_GE(corpus_names().size(), 10u);
}

}  // namespace
}  // namespace sdmesh
