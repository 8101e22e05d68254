#pragma once
// Running the sdmesh executable from a test: its exit code, standard output and standard error.

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace sdmesh::test {

inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct CliRun {
    int code = -1;  ///< exit code, -1 if the process did not exit normally
    std::string out, err;
};

/// Runs `sdmesh <arguments>` through the shell (arguments are not quoted), after `shell_prefix`
/// (a `ulimit -v N;`, variables to set).
inline CliRun run_cli(const std::string& arguments, const std::string& shell_prefix = "") {
    static std::atomic<int> counter{0};
    const std::filesystem::path err_file =
        std::filesystem::temp_directory_path() /
        ("sdmesh_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".err");
    const std::string command = shell_prefix + SDMESH_CLI + " " + arguments + " 2>" + err_file.string();
    CliRun result;
    FILE* pipe = ::popen(command.c_str(), "r");
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) result.out.append(buffer, n);
    const int status = ::pclose(pipe);
    result.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.err = read_text(err_file);
    std::filesystem::remove(err_file);
    return result;
}

/// A fresh folder under the system's temporary folder, removed with everything in it.
class TemporaryFolder {
public:
    explicit TemporaryFolder(const std::string& name)
        : path_(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TemporaryFolder() { std::filesystem::remove_all(path_); }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace sdmesh::test
