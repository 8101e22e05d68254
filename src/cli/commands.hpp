#pragma once
// The subcommands of the `sdmesh` executable. Each returns the process exit code and throws
// sdmesh::Error or UsageError, which main() maps to exit codes.

#include "cli/args.hpp"

namespace sdmesh::cli {

/// Exit codes, documented in README.md.
enum ExitCode : int {
    kSuccess = 0,
    kNotSelfDelaunay = 1,
    kUsage = 2,
    kIoError = 3,
    kUnsupportedFormat = 4,
    kParseError = 5,
    kInvalidMesh = 6,
    kInvalidArgument = 7,
    kNumericalError = 8,
    kInternalError = 70,
};

int run_info(Args& args);
int run_check(Args& args);
int run_repair(Args& args);

}  // namespace sdmesh::cli
