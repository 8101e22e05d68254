#pragma once
// A fixture for tests that run the `sdmesh` executable: a scratch folder per test process, the
// exit code of a command line, and whole-file reads.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace sdmesh::test {

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("sdmesh_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    /// Exit code of `sdmesh ARGUMENTS`; stdout and stderr go to out.txt and err.txt in the folder.
    int run(const std::string& arguments) const {
        const std::string command = std::string(SDMESH_CLI) + " " + arguments + " >" + (dir_ / "out.txt").string() +
                                    " 2>" + (dir_ / "err.txt").string();
        const int status = std::system(command.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    [[nodiscard]] static std::string read(const std::filesystem::path& path) {
        std::ifstream in(path, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    }
    std::filesystem::path dir_;
};

}  // namespace sdmesh::test
