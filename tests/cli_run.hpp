#pragma once
// A GoogleTest fixture over cli_runner.hpp for tests that run the `sdmesh` executable: a scratch
// folder per test, the exit code of a command line, its output and errors kept in the folder.

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "cli_runner.hpp"

namespace sdmesh::test {

class CliTest : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = std::make_unique<TemporaryFolder>(
            "sdmesh_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        dir_ = folder_->path();
    }
    void TearDown() override { folder_.reset(); }

    /// Exit code of `sdmesh ARGUMENTS`; stdout and stderr are kept as out.txt and err.txt in the folder.
    int run(const std::string& arguments) const {
        const CliRun r = run_cli(arguments);
        std::ofstream(dir_ / "out.txt", std::ios::binary) << r.out;
        std::ofstream(dir_ / "err.txt", std::ios::binary) << r.err;
        return r.code;
    }
    [[nodiscard]] static std::string read(const std::filesystem::path& path) { return read_text(path); }

    std::filesystem::path dir_;

private:
    std::unique_ptr<TemporaryFolder> folder_;
};

}  // namespace sdmesh::test
