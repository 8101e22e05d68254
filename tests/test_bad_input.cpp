// The bad-input corpus (bad_input_cases.hpp) against the library and every command that reads a
// mesh: each broken file and each defective mesh, in every format that can hold it, gives the
// documented exit code with one line on stderr naming the file, and the documented exception.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <string>
#include <vector>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "bad_input_cases.hpp"
#include "cli_runner.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/shapes.hpp"
#include "sdmesh/triangulation.hpp"

namespace sdmesh {
namespace {

namespace fs = std::filesystem;
using test::BadFile;
using test::BadMesh;
using test::CliRun;
using test::CommandCodes;

// Every command that reads a mesh, with the arguments that make it run on a small mesh; MESH and
// DIR are replaced by the input file and a scratch folder (which holds f.txt for poisson).
struct Command {
    const char* name;
    const char* arguments;
    int CommandCodes::*code;
};
constexpr Command kCommands[] = {
    {"info", "info MESH", &CommandCodes::info},
    {"check", "check MESH", &CommandCodes::check},
    {"repair", "repair MESH DIR/repaired.obj", &CommandCodes::repair},
    {"convert", "convert MESH DIR/converted.obj --max-vertices 2000", &CommandCodes::convert},
    {"operators", "operators MESH --out DIR/operators", &CommandCodes::operators},
    {"intrinsic", "intrinsic MESH --out DIR/intrinsic", &CommandCodes::intrinsic},
    {"eigs", "eigs MESH -k 1 --out DIR/eigs", &CommandCodes::eigs},
    {"geodesic", "geodesic MESH --source 0 --out DIR/geodesic.ply", &CommandCodes::geodesic},
    {"poisson", "poisson MESH --f DIR/f.txt --out DIR/poisson.ply", &CommandCodes::poisson},
    {"heat", "heat MESH --source 0 --time 0.1 --out DIR/heat.ply", &CommandCodes::heat},
    {"decimate", "decimate MESH DIR/decimated.obj --target-ratio 0.5 --convert-first", &CommandCodes::decimate},
};

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
    return text;
}

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// A right-hand side for poisson: one value per vertex.
void write_poisson_rhs(const fs::path& dir, int vertices) {
    std::string text;
    for (int i = 0; i < vertices; ++i) text += "1\n";
    write_bytes(dir / "f.txt", text);
}

// Runs every command on `file` at once (they are independent processes) and checks each exit
// code; a command that fails (exit code 2 or more) must print exactly one line, which names the
// file when the file is at fault (exit codes 3 to 6).
void expect_commands(const fs::path& file, const fs::path& dir, const std::function<int(const Command&)>& expected) {
    std::vector<std::future<CliRun>> runs;
    for (const Command& command : kCommands) {
        const std::string arguments =
            replace_all(replace_all(command.arguments, "MESH", file.string()), "DIR", dir.string());
        runs.push_back(std::async(std::launch::async, [arguments] { return test::run_cli(arguments); }));
    }
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const Command& command = kCommands[i];
        const CliRun r = runs[i].get();
        const int code = expected(command);
        EXPECT_EQ(r.code, code) << "sdmesh " << command.name << " " << file.filename() << ": " << r.err;
        if (code < 2 || r.code < 2) continue;  // 0 and 1 are answers, not errors
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << command.name << ": " << r.err;
        if (code >= 3 && code <= 6) {
            EXPECT_NE(r.err.find(file.string()), std::string::npos) << command.name << " does not name the file: " << r.err;
        }
    }
}

std::string test_name(std::string name) {
    std::replace_if(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) == 0; }, '_');
    return name;
}

// ---- broken files ----------------------------------------------------------------------------

class BrokenFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(BrokenFile, EveryCommandGivesTheReadersExitCode) {
    const BadFile& bad = GetParam();
    test::TemporaryFolder folder("sdmesh_broken_" + test_name(bad.name));
    const fs::path file = folder.path() / bad.name;
    write_bytes(file, bad.bytes);
    write_poisson_rhs(folder.path(), 4);

    if (bad.exit_code == 5) {
        EXPECT_THROW(read_mesh(file), ParseError);
    } else {
        EXPECT_THROW(read_mesh(file), UnsupportedFormatError);
    }
    expect_commands(file, folder.path(), [&](const Command&) { return bad.exit_code; });
    EXPECT_FALSE(fs::exists(folder.path() / "repaired.obj"));
    EXPECT_FALSE(fs::exists(folder.path() / "converted.obj"));
}

INSTANTIATE_TEST_SUITE_P(Corpus, BrokenFile, ::testing::ValuesIn(test::broken_files()),
                         [](const auto& param_info) { return test_name(param_info.param.name); });

// ---- defective meshes ------------------------------------------------------------------------

// The formats a mesh is written in: the writers' (OBJ, OFF, PLY binary and ascii, gzip) and STL.
enum class Written { obj, off, ply_binary, ply_ascii, obj_gz, ply_gz, stl_binary, stl_ascii };
constexpr std::pair<Written, const char*> kWritten[] = {
    {Written::obj, ".obj"},          {Written::off, ".off"},       {Written::ply_binary, ".ply"},
    {Written::ply_ascii, "_ascii.ply"}, {Written::obj_gz, ".obj.gz"}, {Written::ply_gz, ".ply.gz"},
    {Written::stl_binary, ".stl"},   {Written::stl_ascii, "_ascii.stl"},
};

struct MeshInFormat {
    BadMesh bad;
    Written format;
    std::string file_name;
    bool run_commands;  ///< the commands run on one format per mesh, a different one from mesh to mesh
};

void PrintTo(const MeshInFormat& mesh, std::ostream* out) { *out << mesh.file_name; }

// Every mesh in every format that can hold it. The library checks run on each file; the commands
// (a process each, so the slow part) on one format per mesh, taken in turn: each file is read back
// to the same mesh, and the commands see nothing but the mesh.
std::vector<MeshInFormat> meshes_in_formats() {
    std::vector<MeshInFormat> cases;
    std::size_t turn = 0;
    for (const BadMesh& bad : test::bad_meshes()) {
        std::vector<MeshInFormat> formats;
        for (const auto& [format, suffix] : kWritten) {
            const bool stl = format == Written::stl_binary || format == Written::stl_ascii;
            if (!stl || bad.stl) formats.push_back({bad, format, bad.name + suffix, false});
        }
        formats[turn++ % formats.size()].run_commands = true;
        cases.insert(cases.end(), formats.begin(), formats.end());
    }
    return cases;
}

void write_in_format(const fs::path& file, const TriangleMesh& mesh, Written format) {
    switch (format) {
        case Written::stl_binary: write_bytes(file, test::binary_stl(mesh)); break;
        case Written::stl_ascii: write_bytes(file, test::ascii_stl(mesh)); break;
        case Written::ply_ascii: {
            WriteOptions ascii;
            ascii.ply_ascii = true;
            write_mesh(file, mesh, ascii);
            break;
        }
        default: write_mesh(file, mesh);
    }
}

class DefectiveMesh : public ::testing::TestWithParam<MeshInFormat> {};

TEST_P(DefectiveMesh, EveryCommandGivesTheDocumentedExitCode) {
    const MeshInFormat& param = GetParam();
    const BadMesh& bad = param.bad;
    test::TemporaryFolder folder("sdmesh_defective_" + test_name(param.file_name));
    const fs::path file = folder.path() / param.file_name;
    write_in_format(file, bad.mesh, param.format);

    // The file holds the mesh (STL welds by position and stores floats: same faces, same shape).
    const TriangleMesh read = read_mesh(file);
    ASSERT_EQ(read.num_faces(), bad.mesh.num_faces());
    if (param.format != Written::stl_binary && param.format != Written::stl_ascii) {
        ASSERT_EQ(read.num_vertices(), bad.mesh.num_vertices());
        EXPECT_TRUE(read.F == bad.mesh.F);
    }
    write_poisson_rhs(folder.path(), read.num_vertices());

    // The library refuses exactly what the commands refuse as an invalid mesh.
    if (bad.codes.convert == 6) {
        EXPECT_THROW(convert(read, {.max_vertices = 2000}), InvalidMeshError);
    } else {
        EXPECT_NO_THROW(convert(read, {.max_vertices = 2000}));
    }
    if (bad.codes.operators == 6) {
        EXPECT_THROW(Triangulation::from_mesh(read), InvalidMeshError);
    } else {
        EXPECT_NO_THROW(Triangulation::from_mesh(read));
    }
    if (param.run_commands)
        expect_commands(file, folder.path(), [&](const Command& command) { return bad.codes.*command.code; });
}

INSTANTIATE_TEST_SUITE_P(Corpus, DefectiveMesh, ::testing::ValuesIn(meshes_in_formats()),
                         [](const auto& param_info) { return test_name(param_info.param.file_name); });

// ---- interruption ----------------------------------------------------------------------------

// Starts `sdmesh arguments...`, waits until a temporary file of an atomic write appears in `dir`
// (the command is writing its output), then sends `signal_number`. The wait status, or -1 if the
// command ended before it was seen writing.
int interrupt_while_writing(const std::vector<std::string>& arguments, const fs::path& dir, int signal_number) {
    std::vector<char*> argv{const_cast<char*>(SDMESH_CLI)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::execv(SDMESH_CLI, argv.data());
        ::_exit(127);
    }
    bool seen_writing = false;
    int status = 0;
    while (!seen_writing && ::waitpid(pid, &status, WNOHANG) == 0) {
        for (const auto& entry : fs::directory_iterator(dir))
            seen_writing = seen_writing || entry.path().filename().string().find(".tmp-") != std::string::npos;
    }
    if (!seen_writing) return -1;
    ::kill(pid, signal_number);
    ::waitpid(pid, &status, 0);
    return status;
}

class Interruption : public ::testing::TestWithParam<int> {};

TEST_P(Interruption, LeavesNoTemporaryAndTheTargetUnchanged) {
    const int signal_number = GetParam();
    test::TemporaryFolder folder("sdmesh_interrupted_" + std::to_string(signal_number));
    const fs::path input = folder.path() / "sphere.ply", target = folder.path() / "out.obj.gz";
    write_mesh(input, make_icosphere(7));  // 327,680 faces: the gzip write takes a while
    const std::string before = "the earlier output\n";
    write_bytes(target, before);

    const int status = interrupt_while_writing({"repair", input.string(), target.string()}, folder.path(), signal_number);
    ASSERT_NE(status, -1) << "sdmesh finished before it was seen writing";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number) << "wait status " << status;
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder.path())) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"out.obj.gz", "sphere.ply"}));
    EXPECT_EQ(test::read_text(target), before);
}

INSTANTIATE_TEST_SUITE_P(Signals, Interruption, ::testing::Values(SIGINT, SIGTERM),
                         [](const auto& param_info) { return param_info.param == SIGINT ? "SIGINT" : "SIGTERM"; });

}  // namespace
}  // namespace sdmesh
