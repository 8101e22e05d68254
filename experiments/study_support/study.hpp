#pragma once
// What the study programs of experiments/ share: their command line, CSV output, corpus meshes,
// meshes of shapes with known spectra, perturbations that keep the vertices and change the
// connectivity (or move the vertices a little), and the connectivity variants every study
// compares: the mesh as it is, its self-Delaunay conversions (split, hybrid) and its iDT.
// Public sdmesh API only.

#include <filesystem>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "sdmesh/mesh.hpp"
#include "sdmesh/triangulation.hpp"

namespace study {

/// `PROGRAM --out DIR [--corpus DIR] [--quick] [--mesh NAME] [--max-faces N]`, the command line of
/// every program in experiments/ (a program ignores what does not concern it).
struct Args {
    std::filesystem::path out;
    std::filesystem::path corpus;
    bool quick = false;  ///< tiny sizes, meshes made in code only: for ctest
    std::string mesh;    ///< only this corpus mesh (a file name), when given
    std::optional<long long> max_faces;  ///< skip corpus meshes with more faces
};

/// Parses the command line; prints the usage and exits with status 2 on a bad one.
Args parse_args(int argc, char** argv, std::string_view program);

/// A study's main(): parses the command line (usage and exit status 2 on a bad one), creates
/// args.out and runs `body`; an exception is printed as one line and gives exit status 1.
int run_study(int argc, char** argv, std::string_view program, int (*body)(const Args&));

/// A CSV table built in memory and written atomically. Doubles are written with 17 digits.
class Csv {
public:
    explicit Csv(std::string_view header) { text_ << header << '\n'; }

    template <typename... Fields>
    void row(const Fields&... fields) {
        text_.precision(17);
        const char* separator = "";
        ((text_ << separator << fields, separator = ","), ...);
        text_ << '\n';
    }

    /// Writes the table to `path` (temporary file, then rename).
    void save(const std::filesystem::path& path) const;

private:
    std::ostringstream text_;
};

/// Reads a corpus mesh, `name` relative to args.corpus.
sdmesh::TriangleMesh corpus_mesh(const Args& args, std::string_view name);

// --- Shapes with known spectra ---------------------------------------------------------------

enum class PolarSurface {
    disk,        ///< unit disk in the z = 0 plane
    hemisphere,  ///< upper unit hemisphere, boundary on the equator
};

/// A disk-like mesh made of `rings` concentric rings around a centre vertex (the pole of the
/// hemisphere), equally spaced in radius (polar angle), each with about 2π·radius/spacing
/// vertices, consecutive rings joined by merging them in angle order: well-shaped triangles,
/// counter-clockwise seen from +z. The outer ring is the boundary.
sdmesh::TriangleMesh make_polar_mesh(PolarSurface surface, int rings);

// --- Perturbations ---------------------------------------------------------------------------

/// Random edge flips that keep every vertex where it is.
struct FlipPerturbation {
    int rounds = 1;               ///< passes over all edges (each face takes part in one flip per pass)
    double probability = 0.3;     ///< chance that an eligible edge is flipped
    double max_dihedral_deg = 10; ///< only edges whose faces are within this angle of coplanar
    double min_angle_deg = 2;     ///< a flip must not create a corner angle below this
};

/// Flips interior edges at random (see FlipPerturbation); an edge is flipped only when its new
/// diagonal does not exist yet and the two new faces are not folded over (their normals agree
/// with the old ones), so the result is a valid manifold mesh on the same vertices.
sdmesh::TriangleMesh flip_random_edges(const sdmesh::TriangleMesh& mesh, const FlipPerturbation& perturbation,
                                       std::mt19937_64& rng);

/// Moves every vertex by a random tangential step of up to `fraction` of the mean edge length
/// and puts it back on the unit sphere (sphere = true) or leaves it in its plane (z = 0).
/// Vertices on the boundary (z = 0 on the hemisphere, the rim of the disk) move along it.
/// \throws std::runtime_error when a face is folded over (fraction too large).
sdmesh::TriangleMesh jitter_vertices(const sdmesh::TriangleMesh& mesh, double fraction, bool sphere,
                                     std::mt19937_64& rng);

// --- Connectivity variants ---------------------------------------------------------------------

enum class Connectivity { original, split, hybrid, intrinsic };

std::string_view to_string(Connectivity connectivity);

/// A mesh under one of the connectivities. The iDT keeps the vertices (mesh holds the input
/// positions with the input's faces, for drawing); the conversions add vertices after the input's.
struct Variant {
    Connectivity connectivity = Connectivity::original;
    sdmesh::TriangleMesh mesh;
    sdmesh::Triangulation triangulation;
};

/// The mesh under `connectivity`: split = convert() with the interval rule, hybrid = convert()
/// with max_dihedral_deg 10, intrinsic = intrinsic_delaunay().
/// \throws std::runtime_error when a conversion is not certified or the iDT loop does not finish.
Variant make_variant(const sdmesh::TriangleMesh& mesh, Connectivity connectivity);

// --- Measurements --------------------------------------------------------------------------

/// Vertices on a boundary edge, ascending.
std::vector<int> boundary_vertices(const sdmesh::Triangulation& t);

double mean_edge_length(const sdmesh::Triangulation& t);

/// The k smallest eigenvalues of L φ = λ M φ, M barycentric; Dirichlet condition on the
/// boundary vertices when `dirichlet`, Neumann otherwise.
/// \throws std::runtime_error when the solver does not converge.
Eigen::VectorXd smallest_eigenvalues(const sdmesh::Triangulation& t, int k, bool dirichlet = false);

/// Per edge, from the lengths alone: the Delaunay margin π − (α + β) of an interior edge, π/2 − α
/// of a boundary edge (delaunay.hpp); an edge is locally Delaunay iff its margin >= −tolerance.
Eigen::VectorXd delaunay_margins(const sdmesh::Triangulation& t);

/// The smallest margin over the interior edges (+inf without any).
double min_interior_margin(const sdmesh::Triangulation& t);

}  // namespace study
