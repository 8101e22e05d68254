#pragma once
// The subcommands of the `sdmesh` executable. Each returns the process exit code and throws
// sdmesh::Error or UsageError, which main() maps to exit codes.

#include <string>

#include "cli/args.hpp"
#include "sdmesh/error.hpp"

namespace sdmesh::cli {

/// Exit codes, documented in README.md.
enum ExitCode : int {
    kSuccess = 0,
    /// The outputs are written but fall short of what was asked, with one line on stderr saying
    /// how: not self-Delaunay (check, convert, decimate), flip budget exhausted (intrinsic), not
    /// converged (eigs), or a solver's --convert or --intrinsic mesh not Delaunay.
    kFellShort = 1,
    kUsage = 2,
    kIoError = 3,
    kUnsupportedFormat = 4,
    kParseError = 5,
    kInvalidMesh = 6,
    kInvalidArgument = 7,
    kNumericalError = 8,
    kInternalError = 70,
};

/// Runs f(), naming `path` in the message of an InvalidMeshError it throws (the library's
/// messages name elements, the command knows the file).
template <class F>
decltype(auto) about_file(const std::string& path, F&& f) {
    try {
        return f();
    } catch (const InvalidMeshError& e) {
        throw InvalidMeshError(path + ": " + e.what());
    }
}

int run_info(Args& args);
int run_check(Args& args);
int run_repair(Args& args);
int run_convert(Args& args);
int run_decimate(Args& args);
int run_operators(Args& args);
int run_intrinsic(Args& args);
int run_eigs(Args& args);
int run_geodesic(Args& args);
int run_poisson(Args& args);
int run_heat(Args& args);

}  // namespace sdmesh::cli
