// The `sdmesh` command-line tool: dispatches to subcommands and maps exceptions to exit codes.

#include <algorithm>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include <signal.h>

#include "cli/commands.hpp"
#include "io/output_file.hpp"
#include "sdmesh/error.hpp"

namespace {

using namespace sdmesh::cli;

constexpr std::string_view kHelpText = R"(usage: sdmesh COMMAND [ARGS...]   (sdmesh --version: the version)

Commands:
  info MESH                       topology and defects of a mesh, human-readable
  check MESH [--json] [--boundary strict|free] [--tolerance RAD]
                                  Delaunay certificate; exit 0 if self-Delaunay, 1 if not
  convert IN OUT [--method split|hybrid|flip] [--split-rule interval|shell]
          [--max-dihedral DEG] [--coplanar-tolerance RAD] [--boundary strict|free]
          [--max-vertices N] [--tolerance RAD] [--cascade-trials N] [--local-search PASSES]
          [--lower-bound] [--repair] [--no-hausdorff] [--report FILE.json] [--progress]
                                  self-Delaunay conversion; exit 0 if certified, 1 if not
  decimate IN OUT (--target-vertices N | --target-ratio R) [--max-error REL]
          [--boundary strict|free] [--convert-first] [--levels R1,R2,...]
          [--no-hausdorff] [--report FILE.json] [--progress]
                                  Delaunay-preserving edge collapses of a self-Delaunay mesh;
                                  --levels also writes OUT_levelK for each ratio; exit 0 if
                                  the output is self-Delaunay (status reached_target or stalled)
  repair IN OUT [--keep-coincident] [--keep-needles] [--keep-repeated] [--keep-duplicates]
          [--keep-nonmanifold] [--keep-orientation] [--keep-caps] [--keep-unreferenced]
                                  merge coincident vertices, collapse zero-area needles, drop
                                  repeated-index and duplicate faces, give each fan at a
                                  non-manifold vertex its own copy, orient consistently, flip
                                  zero-area caps away, drop unreferenced vertices; each
                                  --keep-... flag turns one of them off
  operators MESH --out DIR [--mass barycentric|circumcentric|mixed|galerkin]
                                  L, M, d0, d1, star0/1/2 as Matrix Market files and report.json in DIR
  intrinsic MESH --out DIR [--mass ...] [--tolerance RAD] [--max-flips N]
                                  the same files for the intrinsic Delaunay triangulation (edge
                                  flips, vertices kept); report.json adds flips, proper, status;
                                  exit 1 if the flips run out of their budget or leave
                                  unflippable edges
  eigs MESH -k K --out DIR [--mass ...] [--convert split|hybrid|flip | --intrinsic] [--sigma S]
          [--tolerance T] [--solver block|spectra] [--progress]
                                  the K smallest eigenpairs of L φ = λ M φ: eigenvalues.csv,
                                  eigenvectors.bin (int32 n, int32 k, k columns of n doubles,
                                  little endian) and report.json in DIR; exit 1 if not
                                  converged (the pairs are then approximations)
  geodesic MESH --source V[,V...] --out FILE.ply [--mass ...] [--convert METHOD | --intrinsic]
          [--time T]              heat-method distance to the nearest source, as the PLY vertex
                                  field `distance`; the report (JSON) goes to stdout
  poisson MESH --f FILE --out FILE.ply [--dirichlet FILE] [--mass ...] [--convert METHOD | --intrinsic]
                                  −Δu = f (f: one value per line), u given on the vertices of
                                  the "VERTEX VALUE" lines of --dirichlet; PLY vertex field `u`
  heat MESH (--u0 FILE | --source V[,V...]) --time T --out FILE.ply [--steps N] [...]
                                  backward Euler heat steps from u0; PLY vertex field `u`

Mesh files: .obj .off .ply .stl, each optionally .gz.
Exit codes: 0 ok, 1 outputs written but short of the goal (not self-Delaunay, not certified,
            flip budget exhausted, not converged; one line on stderr says which), 2 usage,
            3 I/O error, 4 unsupported format, 5 malformed file, 6 invalid mesh,
            7 invalid argument, 8 numerical error, 70 internal error.
)";

struct Command {
    std::string_view name;
    int (*run)(Args&);
};

constexpr Command kCommands[] = {
    {"info", run_info},
    {"check", run_check},
    {"repair", run_repair},
    {"convert", run_convert},
    {"decimate", run_decimate},
    {"operators", run_operators},
    {"intrinsic", run_intrinsic},
    {"eigs", run_eigs},
    {"geodesic", run_geodesic},
    {"poisson", run_poisson},
    {"heat", run_heat},
};

// SIGINT / SIGTERM: remove the temporary files of unfinished writes (finished outputs were renamed
// into place atomically, so no target is ever partial), then die of the signal as the caller
// expects. SA_RESETHAND | SA_NODEFER make the re-raised signal take its default action at once.
extern "C" void remove_temporaries_and_die(int signal_number) {
    sdmesh::io::TemporaryFiles::remove_all();
    ::raise(signal_number);
}

void clean_up_on_interruption() {
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_die;
    action.sa_flags = SA_RESETHAND | SA_NODEFER;
    sigemptyset(&action.sa_mask);
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(signal_number, &action, nullptr);
}

// `sdmesh COMMAND --help`: the command's entry of kHelpText (its first line starts with two
// spaces and the name, continuation lines with more spaces), then the notes common to all.
std::string command_help(std::string_view name) {
    std::string help = "usage: sdmesh ";
    const std::string_view notes = kHelpText.substr(kHelpText.find("\nMesh files:"));
    bool inside = false;
    for (std::size_t at = 0; at < kHelpText.size();) {
        const std::size_t end = kHelpText.find('\n', at) + 1;
        const std::string_view line = kHelpText.substr(at, end - at);
        const bool entry_start = line.size() > 2 && line.substr(0, 2) == "  " && line[2] != ' ';
        if (entry_start) inside = line.substr(2, name.size() + 1) == std::string(name) + " ";
        else if (line.substr(0, 2) != "  ") inside = false;
        if (inside) help += entry_start ? line.substr(2) : line;
        at = end;
    }
    return help.append(notes);
}

bool asks_for_help(const std::vector<std::string>& words) {
    return std::any_of(words.begin() + 1, words.end(), [](const std::string& w) { return w == "--help" || w == "-h"; });
}

int fail(int code, const std::string& message) {
    std::cerr << "sdmesh: " << message << '\n';
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    clean_up_on_interruption();
    const std::vector<std::string> words(argv + 1, argv + argc);
    if (words.empty() || words[0] == "--help" || words[0] == "-h" || words[0] == "help") {
        std::cout << kHelpText;
        return words.empty() ? kUsage : kSuccess;
    }
    if (words[0] == "--version") {
        std::cout << "sdmesh " << SDMESH_VERSION << '\n';
        return kSuccess;
    }
    for (const Command& command : kCommands) {
        if (words[0] != command.name) continue;
        if (asks_for_help(words)) {
            std::cout << command_help(command.name);
            return kSuccess;
        }
        Args args({words.begin() + 1, words.end()});
        try {
            return command.run(args);
        } catch (const UsageError& e) {
            return fail(kUsage, std::string(command.name) + ": " + e.what());
        } catch (const sdmesh::IoError& e) {
            return fail(kIoError, e.what());
        } catch (const sdmesh::UnsupportedFormatError& e) {
            return fail(kUnsupportedFormat, e.what());
        } catch (const sdmesh::ParseError& e) {
            return fail(kParseError, e.what());
        } catch (const sdmesh::InvalidMeshError& e) {
            return fail(kInvalidMesh, e.what());
        } catch (const sdmesh::InvalidArgumentError& e) {
            return fail(kInvalidArgument, e.what());
        } catch (const sdmesh::NumericalError& e) {
            return fail(kNumericalError, e.what());
        } catch (const std::bad_alloc&) {
            return fail(kInternalError, "out of memory");
        } catch (const std::exception& e) {
            return fail(kInternalError, std::string("internal error: ") + e.what());
        }
    }
    return fail(kUsage, "unknown command '" + words[0] + "' (sdmesh --help lists them)");
}
