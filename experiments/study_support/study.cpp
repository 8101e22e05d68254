#include "study.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <unordered_set>

#include <Eigen/Geometry>

#include "sdmesh/convert.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/topology.hpp"

namespace fs = std::filesystem;

namespace study {

Args parse_args(int argc, char** argv, std::string_view program) {
    const auto usage_error = [&](const std::string& message) {
        std::cerr << program << ": " << message << "\nusage: " << program
                  << " --out DIR [--corpus DIR] [--quick] [--mesh NAME] [--max-faces N]\n";
        std::exit(2);
    };
    Args args;
    args.corpus = SDMESH_CORPUS_DIR;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const auto value = [&]() -> std::string_view {
            if (i + 1 >= argc) usage_error(std::string(arg) + " needs a value");
            return argv[++i];
        };
        if (arg == "--out") {
            args.out = value();
        } else if (arg == "--corpus") {
            args.corpus = value();
        } else if (arg == "--quick") {
            args.quick = true;
        } else if (arg == "--mesh") {
            args.mesh = value();
        } else if (arg == "--max-faces") {
            const std::string_view text = value();
            long long n = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), n);
            if (error != std::errc{} || end != text.data() + text.size() || n < 0)
                usage_error("--max-faces must be a non-negative integer, got '" + std::string(text) + "'");
            args.max_faces = n;
        } else {
            usage_error("unknown argument '" + std::string(arg) + "'");
        }
    }
    if (args.out.empty()) usage_error("--out DIR is required");
    return args;
}

int run_study(int argc, char** argv, std::string_view program, int (*body)(const Args&)) {
    const Args args = parse_args(argc, argv, program);
    try {
        fs::create_directories(args.out);
        return body(args);
    } catch (const std::exception& error) {
        std::cerr << program << ": " << error.what() << '\n';
        return 1;
    }
}

void Csv::save(const fs::path& path) const { sdmesh::write_text_file(path, text_.str()); }

sdmesh::TriangleMesh corpus_mesh(const Args& args, std::string_view name) {
    return sdmesh::read_mesh(args.corpus / name);
}

// --- Shapes ----------------------------------------------------------------------------------

sdmesh::TriangleMesh make_polar_mesh(PolarSurface surface, int rings) {
    if (rings < 1) throw std::invalid_argument("make_polar_mesh: rings must be >= 1");
    const bool disk = surface == PolarSurface::disk;
    const double spacing = (disk ? 1.0 : std::numbers::pi / 2) / rings;  // radius or polar angle
    std::vector<Eigen::Vector3d> points{Eigen::Vector3d(0, 0, disk ? 0 : 1)};  // the centre
    struct Ring {
        int first, count;
        double offset;  // angle of its first vertex
    };
    std::vector<Ring> ring_list{{0, 1, 0.0}};
    for (int i = 1; i <= rings; ++i) {
        const double along = i * spacing;
        const double radius = disk ? along : std::sin(along);  // distance from the axis
        const int count = std::max(6, static_cast<int>(std::lround(2 * std::numbers::pi * radius / spacing)));
        const double offset = (i % 2) * std::numbers::pi / count;  // stagger consecutive rings
        ring_list.push_back({static_cast<int>(points.size()), count, offset});
        for (int j = 0; j < count; ++j) {
            const double angle = offset + 2 * std::numbers::pi * j / count;
            const double z = disk ? 0.0 : std::cos(along);
            points.emplace_back(radius * std::cos(angle), radius * std::sin(angle), i == rings ? 0.0 : z);
        }
    }
    std::vector<Eigen::Vector3i> faces;
    for (int i = 1; i <= rings; ++i) {
        const Ring& inner = ring_list[i - 1];
        const Ring& outer = ring_list[i];
        const auto angle = [](const Ring& r, int j) { return r.offset + 2 * std::numbers::pi * j / r.count; };
        const auto vertex = [](const Ring& r, int j) { return r.first + j % r.count; };
        const int inner_steps = inner.count == 1 ? 0 : inner.count;  // the centre is never advanced
        int a = 0, b = 0;
        while (a < inner_steps || b < outer.count) {
            const bool advance_outer =
                a == inner_steps || (b < outer.count && angle(outer, b + 1) <= angle(inner, a + 1));
            if (advance_outer) {
                faces.emplace_back(vertex(inner, a), vertex(outer, b), vertex(outer, b + 1));
                ++b;
            } else {
                faces.emplace_back(vertex(inner, a), vertex(outer, b), vertex(inner, a + 1));
                ++a;
            }
        }
    }
    sdmesh::TriangleMesh mesh;
    mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (std::size_t v = 0; v < points.size(); ++v) mesh.V.row(static_cast<Eigen::Index>(v)) = points[v].transpose();
    mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
    return mesh;
}

// --- Perturbations ---------------------------------------------------------------------------

namespace {

Eigen::Vector3d corner(const sdmesh::TriangleMesh& mesh, int v) { return mesh.V.row(v).transpose(); }

Eigen::Vector3d face_normal(const sdmesh::TriangleMesh& mesh, int a, int b, int c) {
    return (corner(mesh, b) - corner(mesh, a)).cross(corner(mesh, c) - corner(mesh, a));
}

double min_corner_angle(const sdmesh::TriangleMesh& mesh, int a, int b, int c) {
    const int v[3] = {a, b, c};
    double smallest = std::numbers::pi;
    for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d u = corner(mesh, v[(k + 1) % 3]) - corner(mesh, v[k]);
        const Eigen::Vector3d w = corner(mesh, v[(k + 2) % 3]) - corner(mesh, v[k]);
        smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)));
    }
    return smallest;
}

std::uint64_t edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

std::vector<char> boundary_flags(const sdmesh::TriangleMesh& mesh) {
    const sdmesh::EdgeTable edges = sdmesh::build_edge_table(mesh.F, mesh.num_vertices());
    std::vector<char> on_boundary(static_cast<std::size_t>(mesh.num_vertices()), 0);
    for (int e = 0; e < edges.num_edges(); ++e)
        if (edges.face_count[e] == 1) on_boundary[edges.E(e, 0)] = on_boundary[edges.E(e, 1)] = 1;
    return on_boundary;
}

}  // namespace

sdmesh::TriangleMesh flip_random_edges(const sdmesh::TriangleMesh& mesh, const FlipPerturbation& perturbation,
                                       std::mt19937_64& rng) {
    constexpr double kDegree = std::numbers::pi / 180;
    sdmesh::TriangleMesh result = mesh;
    Eigen::MatrixX3i& F = result.F;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int round = 0; round < perturbation.rounds; ++round) {
        const sdmesh::EdgeTable edges = sdmesh::build_edge_table(F, result.num_vertices());
        std::unordered_set<std::uint64_t> existing;
        for (int e = 0; e < edges.num_edges(); ++e) existing.insert(edge_key(edges.E(e, 0), edges.E(e, 1)));
        std::vector<int> order(static_cast<std::size_t>(edges.num_edges()));
        std::iota(order.begin(), order.end(), 0);
        std::shuffle(order.begin(), order.end(), rng);
        std::vector<char> touched(static_cast<std::size_t>(result.num_faces()), 0);  // one flip per face per round
        for (const int e : order) {
            if (uniform(rng) >= perturbation.probability || edges.face_count[e] != 2) continue;
            const int h0 = edges.edge_halfedges(e, 0), h1 = edges.edge_halfedges(e, 1);
            const int f0 = h0 / 3, k0 = h0 % 3, f1 = h1 / 3, k1 = h1 % 3;
            if (touched[f0] || touched[f1]) continue;
            // f0 = (a, b, c) and f1 = (b, a, d) around the edge a-b; the flip makes (a, d, c), (d, b, c).
            const int a = F(f0, (k0 + 1) % 3), b = F(f0, (k0 + 2) % 3), c = F(f0, k0), d = F(f1, k1);
            if (F(f1, (k1 + 1) % 3) != b || c == d || existing.contains(edge_key(c, d))) continue;
            const Eigen::Vector3d n0 = face_normal(result, a, b, c).normalized();
            const Eigen::Vector3d n1 = face_normal(result, b, a, d).normalized();
            if (n0.dot(n1) < std::cos(perturbation.max_dihedral_deg * kDegree)) continue;
            const Eigen::Vector3d m0 = face_normal(result, a, d, c), m1 = face_normal(result, d, b, c);
            const Eigen::Vector3d mean_normal = n0 + n1;
            if (m0.dot(mean_normal) <= 0 || m1.dot(mean_normal) <= 0) continue;  // folded over
            const double min_angle = perturbation.min_angle_deg * kDegree;
            if (min_corner_angle(result, a, d, c) < min_angle || min_corner_angle(result, d, b, c) < min_angle)
                continue;
            F.row(f0) = Eigen::RowVector3i(a, d, c);
            F.row(f1) = Eigen::RowVector3i(d, b, c);
            touched[f0] = touched[f1] = 1;
            existing.erase(edge_key(a, b));
            existing.insert(edge_key(c, d));
        }
    }
    return result;
}

sdmesh::TriangleMesh jitter_vertices(const sdmesh::TriangleMesh& mesh, double fraction, bool sphere,
                                     std::mt19937_64& rng) {
    const double step = fraction * mean_edge_length(sdmesh::Triangulation::from_mesh(mesh));
    const std::vector<char> on_boundary = boundary_flags(mesh);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    sdmesh::TriangleMesh result = mesh;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        Eigen::Vector3d p = corner(mesh, v);
        if (on_boundary[v]) {  // on the unit circle in z = 0: move along it
            const double angle = std::atan2(p.y(), p.x()) + step * uniform(rng);
            p = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
        } else {
            const Eigen::Vector3d normal = sphere ? p.normalized() : Eigen::Vector3d::UnitZ();
            Eigen::Vector3d direction(uniform(rng), uniform(rng), uniform(rng));
            direction -= direction.dot(normal) * normal;
            const double length = step * (uniform(rng) + 1) / 2;
            if (direction.norm() > 0) p += length * direction.normalized();
            if (sphere) p.normalize();
        }
        result.V.row(v) = p.transpose();
    }
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const Eigen::Vector3d before = face_normal(mesh, mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
        const Eigen::Vector3d after = face_normal(result, mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
        if (before.dot(after) <= 0)
            throw std::runtime_error("jitter_vertices: face " + std::to_string(f) + " folded over; use a smaller fraction");
    }
    return result;
}

// --- Variants --------------------------------------------------------------------------------

std::string_view to_string(Connectivity connectivity) {
    switch (connectivity) {
        case Connectivity::original: return "original";
        case Connectivity::split: return "split";
        case Connectivity::hybrid: return "hybrid";
        case Connectivity::intrinsic: return "idt";
    }
    return "?";
}

Variant make_variant(const sdmesh::TriangleMesh& mesh, Connectivity connectivity) {
    Variant variant{.connectivity = connectivity, .mesh = mesh, .triangulation = {}};
    if (connectivity == Connectivity::split || connectivity == Connectivity::hybrid) {
        const bool hybrid = connectivity == Connectivity::hybrid;
        sdmesh::ConversionResult converted = sdmesh::convert(
            mesh, {.method = hybrid ? sdmesh::ConvertMethod::hybrid : sdmesh::ConvertMethod::split,
                   .max_dihedral_deg = 10,
                   .measure_hausdorff = false});
        if (converted.report.status != sdmesh::ConvertStatus::certified)
            throw std::runtime_error(std::string(to_string(connectivity)) + " conversion not certified: " +
                                     std::string(sdmesh::to_string(converted.report.status)));
        variant.mesh = std::move(converted.mesh);
    }
    variant.triangulation = sdmesh::Triangulation::from_mesh(variant.mesh);
    if (connectivity == Connectivity::intrinsic) {
        sdmesh::IntrinsicResult idt = sdmesh::intrinsic_delaunay(variant.triangulation);
        if (idt.report.status != "delaunay") throw std::runtime_error("iDT: " + idt.report.status);
        variant.triangulation = std::move(idt.triangulation);
    }
    return variant;
}

// --- Measurements ----------------------------------------------------------------------------

std::vector<int> boundary_vertices(const sdmesh::Triangulation& t) {
    std::vector<char> flag(static_cast<std::size_t>(t.num_vertices), 0);
    for (int e = 0; e < t.num_edges(); ++e)
        if (t.is_boundary(e)) flag[t.E(e, 0)] = flag[t.E(e, 1)] = 1;
    std::vector<int> vertices;
    for (int v = 0; v < t.num_vertices; ++v)
        if (flag[v]) vertices.push_back(v);
    return vertices;
}

double mean_edge_length(const sdmesh::Triangulation& t) { return t.length.mean(); }

Eigen::VectorXd smallest_eigenvalues(const sdmesh::Triangulation& t, int k, bool dirichlet) {
    // Lanczos can miss a member of a large degenerate cluster (the sphere's l(l+1) has 2l+1) when
    // the cluster sits at the end of the wanted range; asking for more keeps it inside.
    const int extra = std::max(10, k / 2);
    sdmesh::EigenOptions options{.k = k + extra};
    if (dirichlet) options.dirichlet_vertices = boundary_vertices(t);
    const int free_vertices = t.num_vertices - static_cast<int>(options.dirichlet_vertices.size());
    options.k = std::min(options.k, free_vertices - 1);
    const sdmesh::EigenResult result =
        sdmesh::smallest_eigenpairs(sdmesh::cotan_laplacian(t), sdmesh::mass_matrix(t), options);
    if (result.report.status != sdmesh::EigenStatus::converged)
        throw std::runtime_error("eigen solver did not converge (" + std::to_string(t.num_vertices) + " vertices)");
    return result.values.head(std::min<Eigen::Index>(k, result.values.size()));
}

Eigen::VectorXd delaunay_margins(const sdmesh::Triangulation& t) {
    Eigen::VectorXd margin(t.num_edges());
    for (int e = 0; e < t.num_edges(); ++e) {
        const int h0 = t.edge_halfedges(e, 0), f0 = h0 / 3, k0 = h0 % 3;
        const double a = t.side(f0, (k0 + 1) % 3), b = t.side(f0, (k0 + 2) % 3);
        if (t.is_boundary(e)) {
            margin[e] = sdmesh::boundary_margin(t.length[e], a, b);
        } else {
            const int h1 = t.edge_halfedges(e, 1), f1 = h1 / 3, k1 = h1 % 3;
            margin[e] = sdmesh::delaunay_margin(t.length[e], a, b, t.side(f1, (k1 + 1) % 3), t.side(f1, (k1 + 2) % 3));
        }
    }
    return margin;
}

double min_interior_margin(const sdmesh::Triangulation& t) {
    const Eigen::VectorXd margin = delaunay_margins(t);
    double smallest = std::numeric_limits<double>::infinity();
    for (int e = 0; e < t.num_edges(); ++e)
        if (!t.is_boundary(e)) smallest = std::min(smallest, margin[e]);
    return smallest;
}

}  // namespace study
