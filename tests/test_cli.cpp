// The `sdmesh` executable: exit codes, one-line errors and the JSON keys scripts rely on.

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bad_input_cases.hpp"
#include "cli_runner.hpp"
#include "meshes.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/shapes.hpp"

namespace sdmesh {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::run_cli;

class Cli : public ::testing::Test {
protected:
    std::string path(const std::string& name) const { return (folder_.path() / name).string(); }
    std::string write_text(const std::string& name, const std::string& text) const {
        std::ofstream(path(name)) << text;
        return path(name);
    }

    // Runs `command` OUT `options` with and without --progress: nothing on stderr without it, with it
    // `lines` in this order, and the same output file either way.
    void expect_progress_lines(const std::string& command, const std::string& options, const std::vector<std::string>& lines) {
        const CliRun quiet = run_cli(command + " " + path("quiet.obj") + options);
        const CliRun loud = run_cli(command + " " + path("loud.obj") + options + " --progress");
        ASSERT_EQ(quiet.code, 0) << quiet.err;
        ASSERT_EQ(loud.code, 0) << loud.err;
        EXPECT_EQ(quiet.err, "");
        size_t at = 0;
        for (const std::string& line : lines) {
            at = loud.err.find(line, at);
            ASSERT_NE(at, std::string::npos) << line << "\n" << loud.err;
        }
        auto read = [](const std::string& file) {
            std::ifstream in(file);
            return std::string(std::istreambuf_iterator<char>(in), {});
        };
        EXPECT_EQ(read(path("loud.obj")), read(path("quiet.obj")));
    }

private:
    test::TemporaryFolder folder_{"sdmesh_cli"};
};

const std::string kBunny = std::string(SDMESH_TEST_DATA_DIR) + "/bunny.obj";

TEST_F(Cli, CheckJsonHasTheDocumentedKeys) {
    const CliRun r = run_cli("check " + kBunny + " --json");
    EXPECT_EQ(r.code, 1) << r.err;  // the bunny has non-Delaunay edges
    for (const char* key :
         {"vertices", "faces", "edges", "components", "boundary_edges", "boundary_loops", "nonmanifold_edges",
          "nonmanifold_vertices", "degenerate_faces", "euler_characteristic", "interior_edges",
          "non_delaunay_edges", "boundary_obtuse_edges", "min_delaunay_margin", "negative_dual_cells",
          "negative_cotan_weights", "gabriel_violations", "collinear_faces", "self_delaunay"})
        EXPECT_NE(r.out.find(std::string(1, '"').append(key).append("\": ")), std::string::npos) << key;
    EXPECT_NE(r.out.find("\"faces\": 3674"), std::string::npos);
    EXPECT_NE(r.out.find("\"self_delaunay\": false"), std::string::npos);
}

TEST_F(Cli, ConvertReportHasTheDocumentedKeys) {
    const CliRun r = run_cli("convert " + kBunny + " " + path("bunny_sd.obj") +
                             " --lower-bound --cascade-trials 2 --report " + path("report.json"));
    EXPECT_EQ(r.code, 0) << r.err;
    for (const char* key : {"input_vertices", "output_vertices", "input_non_delaunay_edges",
                            "input_nonflat_non_delaunay_edges", "flips", "splits", "unflippable_edges",
                            "skipped_splits", "removed_points", "fewest_points_saved", "added_vertices_lower_bound",
                            "cascade_trials", "coplanar_tolerance",
                            "status", "seconds",
                            "hausdorff_rel", "certificate"})
        EXPECT_NE(r.out.find(std::string(1, '"').append(key).append("\": ")), std::string::npos) << key;
    EXPECT_NE(r.out.find("\"status\": \"certified\""), std::string::npos);
    EXPECT_EQ(r.out.find("\"added_vertices_lower_bound\": -1"), std::string::npos);  // asked for: computed
    EXPECT_NE(r.out.find("\"cascade_trials\": 2"), std::string::npos);
    std::ifstream report(path("report.json"));
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(report), {}), r.out);
    EXPECT_EQ(run_cli("check " + path("bunny_sd.obj")).code, 0);
}

// The number after "key": in a JSON report.
double json_number(const std::string& json, const std::string& key) {
    const std::string quoted = "\"" + key + "\": ";
    const size_t at = json.find(quoted);
    return at == std::string::npos ? std::numeric_limits<double>::quiet_NaN() : std::stod(json.substr(at + quoted.size()));
}

// Scopia's switch plate: its six-digit coordinates leave its triangles 1e-6 rad off one plane,
// which split takes for folds at the default tolerance. A coplanar tolerance above that flips
// across them instead: fewer vertices, and the report says how far the surface moved.
TEST_F(Cli, ACoplanarToleranceFlipsWhatRoundingBent) {
    const std::string plate = std::string(SDMESH_TEST_DATA_DIR) + "/scopia_switch_plate.obj";
    const CliRun exact = run_cli("convert " + plate + " " + path("exact.obj"));
    const CliRun bent = run_cli("convert " + plate + " " + path("bent.obj") + " --coplanar-tolerance 1e-5");
    ASSERT_EQ(exact.code, 0) << exact.err;
    ASSERT_EQ(bent.code, 0) << bent.err;
    EXPECT_EQ(json_number(exact.out, "coplanar_tolerance"), 1e-10);
    EXPECT_EQ(json_number(bent.out, "coplanar_tolerance"), 1e-5);
    EXPECT_LT(2 * json_number(bent.out, "output_vertices"), json_number(exact.out, "output_vertices"));
    EXPECT_EQ(json_number(exact.out, "hausdorff_rel"), 0.0);
    EXPECT_GT(json_number(bent.out, "hausdorff_rel"), 0.0);
    EXPECT_LT(json_number(bent.out, "hausdorff_rel"), 1e-6);
    EXPECT_EQ(run_cli("check " + path("bent.obj")).code, 0);
    const CliRun flat = run_cli("convert " + plate + " " + path("flat.obj") + " --coplanar-tolerance 1.6");
    EXPECT_EQ(flat.code, 7);
    EXPECT_NE(flat.err.find("coplanar_tolerance must be in [0, π/2) radians, got 1.6"), std::string::npos) << flat.err;
}

TEST_F(Cli, AConversionThatIsNotCertifiedSaysWhyInOneLine) {
    // The bunny needs about 280 new vertices: a budget of 1,850 (11 more) runs out.
    CliRun r = run_cli("convert " + kBunny + " " + path("budget.obj") + " --max-vertices 1850");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("not certified (budget_exhausted at 1850 vertices"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--max-vertices"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--coplanar-tolerance flips between faces that a file's rounding bent"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("--method hybrid flips nearly flat folds"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    r = run_cli("convert " + kBunny + " " + path("budget.obj") + " --method hybrid --max-dihedral 0.1 --max-vertices 1850");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("a larger --max-dihedral flips more folds"), std::string::npos) << r.err;
    // An obtuse triangle alone: no flip can make its boundary edge's angle acute.
    const std::string obtuse = write_text("obtuse.obj", "v 0 0 0\nv 2 0 0\nv 1 0.2 0\nf 1 2 3\n");
    r = run_cli("convert " + obtuse + " " + path("flipped.obj") + " --method flip");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("0 non-Delaunay edges and 1 obtuse boundary edges that flips cannot fix; --method split"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // Cascades deeper than doubles resolve: the splits skipped are counted and named.
    const std::string plate = std::string(SDMESH_TEST_DATA_DIR) + "/scopia_switch_plate.obj";
    r = run_cli("convert " + plate + " " + path("plate.obj") + " --cascade-trials 8");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("splits skipped where the point fell on a vertex in double precision; --method hybrid"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.out.find("\"skipped_splits\": 0"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The solvers solve on a --convert mesh that is not certified, write their outputs, say so in
// one line and exit 1.
TEST_F(Cli, SolversSayWhenTheirConvertedMeshIsNotCertified) {
    const std::string obtuse = write_text("obtuse.obj", "v 0 0 0\nv 2 0 0\nv 1 0.2 0\nf 1 2 3\n");
    const std::string f = write_text("f.txt", "1\n0\n0\n");
    const std::vector<std::pair<std::string, std::string>> commands = {
        {"eigs", "eigs " + obtuse + " -k 2 --out " + path("eigs")},
        {"geodesic", "geodesic " + obtuse + " --source 0 --out " + path("distance.ply")},
        {"poisson", "poisson " + obtuse + " --f " + f + " --dirichlet " + write_text("d.txt", "2 0\n") + " --out " +
                        path("u.ply")},
        {"heat", "heat " + obtuse + " --source 0 --time 0.1 --out " + path("heat.ply")}};
    for (const auto& [command, line] : commands) {
        const CliRun r = run_cli(line + " --convert flip");
        EXPECT_EQ(r.code, 1) << line << "\n" << r.err;
        EXPECT_EQ(r.err, "sdmesh " + command + ": " + obtuse +
                             ": the --convert flip mesh is not certified (not_certified, 0 non-Delaunay edges and 1 "
                             "obtuse boundary edges left); sdmesh convert says more\n")
            << line;
        EXPECT_NE(r.out.find("\"conversion_status\": \"not_certified\""), std::string::npos) << line << r.out;
        EXPECT_EQ(run_cli(line).code, 0) << line;  // on the mesh as read
    }
    for (const char* output : {"eigs/eigenvalues.csv", "distance.ply", "u.ply", "heat.ply"})
        EXPECT_TRUE(fs::exists(path(output))) << output;
}

TEST_F(Cli, NoHausdorffReportsNullInsteadOfADistance) {
    const std::string hybrid = "convert " + kBunny + " " + path("bunny_hybrid.obj") + " --method hybrid";
    const CliRun measured = run_cli(hybrid);
    const CliRun skipped = run_cli(hybrid + " --no-hausdorff --progress");
    EXPECT_EQ(measured.code, 0) << measured.err;
    EXPECT_EQ(skipped.code, 0) << skipped.err;
    EXPECT_EQ(measured.out.find("\"hausdorff_rel\": null"), std::string::npos);
    EXPECT_EQ(measured.out.find("\"hausdorff_rel\": 0,"), std::string::npos);  // hybrid flips move the bunny
    EXPECT_NE(skipped.out.find("\"hausdorff_rel\": null"), std::string::npos) << skipped.out;
    EXPECT_EQ(skipped.err.find("Hausdorff"), std::string::npos) << skipped.err;
}

// --progress names each phase as it starts (and, on long runs, each phase's counts once a second).
TEST_F(Cli, ConvertProgressNamesEachPhase) {
    expect_progress_lines("convert " + kBunny, " --local-search 2",
                          {"convert: reading " + kBunny + "\n", "convert: checking the input, 1839 vertices and 3674 faces\n",
                           " edges not locally Delaunay, 236 of them folds\n", "convert: removing the points no longer needed, ",
                           "convert: the fewest points per input edge, ", "convert: local search, pass 1 of 2, ",
                           "convert: local search, pass 2 of 2, ", "convert: certifying the output\n",
                           "convert: writing " + path("loud.obj") + "\n"});
}

// decimate's too, through the conversion that --convert-first runs.
TEST_F(Cli, DecimateProgressNamesEachPhase) {
    expect_progress_lines("decimate " + kBunny, " --convert-first --target-ratio 0.5",
                          {"decimate: reading " + kBunny + "\n", "convert: checking the input, 1839 vertices and 3674 faces\n",
                           "convert: certifying the output\n", "decimate: checking the input, ",
                           "decimate: queueing the collapses of ", "decimate: certifying the output\n",
                           "decimate: measuring the Hausdorff distance to the input\n",
                           "decimate: writing " + path("loud.obj") + "\n"});
}

TEST_F(Cli, EveryCommandPrintsItsOwnHelp) {
    const std::vector<std::string> commands = {"info",      "check",     "repair", "convert",  "decimate", "operators",
                                               "intrinsic", "eigs",      "geodesic", "poisson", "heat"};
    for (const std::string& command : commands) {
        const CliRun r = run_cli(command + " --help");
        EXPECT_EQ(r.code, 0) << command << ": " << r.err;
        EXPECT_EQ(r.out.rfind("usage: sdmesh " + command + " ", 0), 0u) << r.out;
        EXPECT_NE(r.out.find("Exit codes:"), std::string::npos) << command;
        for (const std::string& other : commands)  // no other command's entry
            EXPECT_EQ(r.out.find("\n  " + other + " "), std::string::npos) << command << " shows " << other;
    }
    EXPECT_NE(run_cli("eigs -h").out.find("--tolerance T"), std::string::npos);
}

TEST_F(Cli, PrintsItsVersion) {
    const CliRun r = run_cli("--version");
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.out, "sdmesh " SDMESH_TEST_VERSION "\n");
}

TEST_F(Cli, SelfDelaunayMeshExitsZero) {
    write_mesh(path("sphere.off"), make_icosphere(2));
    const CliRun r = run_cli("check " + path("sphere.off"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("self-Delaunay"), std::string::npos);
    EXPECT_EQ(run_cli("info " + path("sphere.off")).code, 0);
}

TEST_F(Cli, GeodesicReportsTheVerticesItsSourcesDoNotReach) {
    // Two unit spheres apart: the sources reach one of them, whose farthest point is antipodal.
    const TriangleMesh sphere = make_icosphere(3);
    const int n = sphere.num_vertices();
    TriangleMesh two{.V = Eigen::MatrixX3d(2 * n, 3), .F = Eigen::MatrixX3i(2 * sphere.num_faces(), 3)};
    two.V << sphere.V, sphere.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
    two.F << sphere.F, sphere.F.array() + n;
    write_mesh(path("two_spheres.off"), two);
    const CliRun r = run_cli("geodesic " + path("two_spheres.off") + " --source 0 --out " + path("d.ply"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\"unreached_vertices\": " + std::to_string(n) + ","), std::string::npos) << r.out;
    EXPECT_NEAR(json_number(r.out, "max_distance"), std::numbers::pi, 0.05 * std::numbers::pi) << r.out;
}

TEST_F(Cli, BoundaryPolicyChangesTheVerdict) {
    write_mesh(path("obtuse.obj"), test::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 0.1, 0}}, {{0, 1, 2}}));
    EXPECT_EQ(run_cli("check " + path("obtuse.obj")).code, 1);
    EXPECT_EQ(run_cli("check " + path("obtuse.obj") + " --boundary free").code, 0);
}

TEST_F(Cli, NonManifoldMeshIsReportedNotRejected) {
    const std::string fin = write_text("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    const CliRun r = run_cli("check " + fin + " --json");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.out.find("\"nonmanifold_edges\": 1"), std::string::npos);
    EXPECT_NE(r.err.find("edge (0, 1) has more than two faces"), std::string::npos) << r.err;
}

TEST_F(Cli, ConvertPointsToRepairWhereItCanHelp) {
    // A fin (an edge with three faces) is what repair mends; a coordinate that is not finite is not.
    const std::string fin = write_text("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    const std::string hint = "(--repair mends what it safely can)";
    CliRun r = run_cli("convert " + fin + " " + path("out.ply"));
    EXPECT_EQ(r.code, 6);
    EXPECT_NE(r.err.find("edge (0, 1) has more than two faces"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(hint), std::string::npos) << r.err;
    EXPECT_EQ(run_cli("convert " + fin + " " + path("out.ply") + " --repair").code, 0);
    const std::string nan = write_text("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    r = run_cli("convert " + nan + " " + path("out.ply"));
    EXPECT_EQ(r.code, 6);
    EXPECT_EQ(r.err.find(hint), std::string::npos) << r.err;
}

TEST_F(Cli, RepairWeldsAndOrientsASoup) {
    // Two triangles of a square written as a soup, the second one wound the other way.
    const std::string soup = write_text("soup.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\n"
                                                    "f 1 2 3\nf 4 6 5\nf 4 6 6\n");
    const CliRun r = run_cli("repair " + soup + " " + path("fixed.off"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\"merged_vertices\": 2"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"flipped_faces\": 1"), std::string::npos) << r.out;
    const TriangleMesh fixed = read_mesh(path("fixed.off"));
    EXPECT_EQ(fixed.num_vertices(), 4);
    EXPECT_EQ(fixed.num_faces(), 2);
    EXPECT_EQ(run_cli("check " + path("fixed.off") + " --json").code, 0);  // two right triangles
}

TEST_F(Cli, ErrorsHaveDistinctExitCodesAndOneLine) {
    auto expect_error = [](const std::string& arguments, int code, const std::string& mention) {
        const CliRun r = run_cli(arguments);
        EXPECT_EQ(r.code, code) << arguments << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << arguments << "\n" << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << arguments << "\n" << r.err;
        EXPECT_TRUE(r.out.empty()) << arguments;
    };
    expect_error("check " + path("missing.obj"), 3, "missing.obj");
    expect_error("check " + write_text("mesh.xyz", "1 2 3\n"), 4, "mesh.xyz");
    expect_error("check " + write_text("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), 5, "bad.obj");
    expect_error("check " + write_text("nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 6, "vertex 0");
    expect_error("check " + kBunny + " --boundary sideways", 2, "--boundary");
    expect_error("check", 2, "usage");
    expect_error("check " + kBunny + " --frobnicate", 2, "--frobnicate");
    expect_error("convert " + kBunny + " " + path("out.obj") + " --cascade-trials -1", 2, "--cascade-trials");
    expect_error("transmogrify " + kBunny, 2, "transmogrify");
    expect_error("geodesic " + write_text("nothing.off", "OFF\n0 0 0\n") + " --source 0 --out " +
                     path("d.ply"),
                 7, "nothing.off has no edges");
    // Two corners of a skewed grid have negative circumcentric cells, so M + tL is not definite.
    write_mesh(path("skewed.obj"), make_grid(4, 4, 4.0, 4.0, 3.0));
    expect_error("heat " + path("skewed.obj") + " --source 0 --time 1e-3 --mass circumcentric --out " + path("u.ply"),
                 8, "skewed.obj: heat: M + tL: Cholesky: the matrix is not positive definite within rounding");
    // Missing required options, for every command that has them.
    expect_error("operators " + kBunny, 2, "--out DIR is required");
    expect_error("intrinsic " + kBunny, 2, "--out DIR is required");
    expect_error("eigs " + kBunny + " --out " + path("e"), 2, "-k K");
    expect_error("geodesic " + kBunny, 2, "--source and --out are required");
    expect_error("poisson " + kBunny, 2, "--f and --out are required");
    expect_error("heat " + kBunny, 2, "are required");
}

// A gzip bomb of vertex lines would grow into coordinates three times its text: what the
// process may not hold is refused with exit code 3, naming the file and the budget, instead of
// running out of memory. A 1 GB address-space limit makes the budget (a sixteenth) 61 MiB.
TEST_F(Cli, MeshBeyondTheMemoryBudgetIsRefused) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer maps terabytes of shadow memory: no address-space limit can hold the CLI";
#endif
    // One thread each: every thread maps a stack and a malloc arena, which the limit counts.
    const std::string limited = "ulimit -v 1000000; OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 ";
    auto write_bomb = [&](const std::string& name, std::size_t vertices) {
        std::string text;
        text.reserve(8 * vertices);
        for (std::size_t i = 0; i < vertices; ++i) text += "v 0 0 0\n";
        std::ofstream(path(name), std::ios::binary) << test::gzip_bytes(text);
        return path(name);
    };
    // 48 MiB of coordinates are within the budget, 192 MiB are not.
    const CliRun within = run_cli("info " + write_bomb("small.obj.gz", 2 << 20), limited);
    EXPECT_EQ(within.code, 0) << within.err;
    EXPECT_NE(within.out.find("2097152"), std::string::npos) << within.out;
    const std::string bomb = write_bomb("bomb.obj.gz", 8 << 20);
    EXPECT_LT(fs::file_size(bomb), 1u << 20);
    const CliRun refused = run_cli("info " + bomb, limited);
    EXPECT_EQ(refused.code, 3) << refused.err;
    EXPECT_EQ(refused.err, "sdmesh: " + bomb + ": its vertices and faces take more than 61 MiB, the most a mesh read "
                                               "may take (a sixteenth of the memory this process may use)\n");
}

// Outputs that cannot be written are refused before the work, not after it, and nothing is
// written then (convert used to write its mesh, then fail on the report's missing folder).
TEST_F(Cli, OutputsThatCannotBeWrittenAreRefusedFirst) {
    const std::string mesh = path("converted.obj"), missing = path("no/such/folder");
    const std::string a_file = write_text("a_file.txt", "not a folder\n");
    const std::string a_folder = path("folder.obj");
    fs::create_directory(a_folder);
    struct Case {
        std::string arguments;
        int code;
        std::string message;
    };
    const std::vector<Case> cases = {
        {"convert " + kBunny + " " + mesh + " --report " + missing + "/r.json", 3,
         missing + "/r.json: cannot create file: No such file or directory"},
        {"convert " + kBunny + " " + missing + "/out.obj", 3, missing + "/out.obj: cannot create file: "},
        {"convert " + kBunny + " " + path("out.stl"), 4, "writing STL is not supported"},
        {"convert " + kBunny + " " + a_folder, 3, a_folder + ": cannot create file: Is a directory"},
        {"convert " + kBunny + " " + mesh + " --report " + a_folder, 3, a_folder + ": cannot create file: "},
        {"decimate " + kBunny + " " + mesh + " --convert-first --target-ratio 0.5 --report " + missing + "/r.json", 3,
         missing + "/r.json: cannot create file: "},
        {"repair " + kBunny + " " + missing + "/out.obj", 3, missing + "/out.obj: cannot create file: "},
        {"geodesic " + kBunny + " --source 0 --out " + path("distance.obj"), 7,
         "vertex fields can only be written to PLY files"},
        {"heat " + kBunny + " --source 0 --time 1 --out " + missing + "/u.ply", 3, "cannot create file: "},
        {"eigs " + kBunny + " -k 3 --out " + a_file + "/eigs", 3,
         a_file + "/eigs: cannot create the output folder: " + a_file + " is not a folder"},
        {"operators " + kBunny + " --out " + a_file, 3, "cannot create the output folder"},
    };
    for (const Case& c : cases) {
        const CliRun r = run_cli(c.arguments);
        EXPECT_EQ(r.code, c.code) << c.arguments << "\n" << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.arguments << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(mesh)) << c.arguments;
    }
}

// A malformed command line gets one line naming the command, the option and the value at fault;
// counts and budgets are whole numbers in a stated range (1e30 used to wrap around to a negative
// vertex budget, 2.5 was cut to 2).
TEST_F(Cli, UsageErrorsNameTheCommandTheOptionAndTheValue) {
    const std::string out = " " + path("out.obj");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"convert " + kBunny + out + " --max-vertices 1e30",
         "convert: --max-vertices expects a whole number from 0 to 2147483647, got '1e30'"},
        {"convert " + kBunny + out + " --max-vertices 2.5",
         "convert: --max-vertices expects a whole number from 0 to 2147483647, got '2.5'"},
        {"convert " + kBunny + out + " --cascade-trials -1",
         "convert: --cascade-trials expects a whole number from 0 to 1000, got '-1'"},
        {"convert " + kBunny + out + " --local-search nan",
         "convert: --local-search expects a whole number from 0 to 100, got 'nan'"},
        {"convert " + kBunny + out + " --method best", "convert: --method must be split|hybrid|flip, got 'best'"},
        {"convert " + kBunny + out + " --max-dihedral ten", "convert: --max-dihedral expects a number, got 'ten'"},
        {"decimate " + kBunny + out + " --target-vertices 0",
         "decimate: --target-vertices expects a whole number from 1 to 2147483647, got '0'"},
        {"decimate " + kBunny + out + " --target-ratio 0.5 --boundary sideways",
         "decimate: --boundary must be strict|free, got 'sideways'"},
        {"intrinsic " + kBunny + " --out " + path("i") + " --max-flips 1.5",
         "intrinsic: --max-flips expects a whole number from 0 to 9007199254740992, got '1.5'"},
        {"eigs " + kBunny + " --out " + path("e") + " -k 2.5",
         "eigs: -k expects a whole number from 1 to 1000000000, got '2.5'"},
        {"eigs " + kBunny + " --out " + path("e") + " -k 4 --convert best",
         "eigs: --convert must be split|hybrid|flip, got 'best'"},
        {"heat " + kBunny + " --out " + path("h.ply") + " --time 1 --source 0 --steps -3",
         "heat: --steps expects a whole number from 0 to 1000000000, got '-3'"},
        {"check " + kBunny + " --boundary sideways", "check: --boundary must be strict|free, got 'sideways'"},
        {"check " + kBunny + " --tolerance", "check: --tolerance needs a value"},
    };
    for (const auto& [arguments, message] : cases) {
        const CliRun r = run_cli(arguments);
        EXPECT_EQ(r.code, 2) << arguments;
        EXPECT_EQ(r.err, "sdmesh: " + message + "\n") << arguments;
        EXPECT_TRUE(r.out.empty()) << arguments;
    }
    const CliRun missing = run_cli("operators " + kBunny);
    EXPECT_EQ(missing.err.rfind("sdmesh: operators: --out DIR is required; usage: sdmesh operators MESH", 0), 0u)
        << missing.err;
}

}  // namespace
}  // namespace sdmesh
