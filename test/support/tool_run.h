#pragma once
// Running the room_reverb command-line tool (or another command) from a test, as a user
// would, and capturing its exit code and output. Header-only: ROOM_REVERB_TOOL (the tool's
// path) is a compile definition of the test executables.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace room_reverb::test {

struct ToolRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs a shell command line (a helper script, a browser driver...) the same way.
inline ToolRun runCommand(const std::string& command_line) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("room_reverb_tool_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out_file = (dir / "out.txt").string();
  const std::string err_file = (dir / "err.txt").string();
  const std::string command = command_line + " >" + out_file + " 2>" + err_file;
  const int status = std::system(command.c_str());
  ToolRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::stringstream out, err;
  out << std::ifstream(out_file).rdbuf();
  err << std::ifstream(err_file).rdbuf();
  run.out = out.str();
  run.err = err.str();
  return run;
}

// `args` is appended to the tool's path as a shell command line.
inline ToolRun runTool(const std::string& args) { return runCommand(std::string(ROOM_REVERB_TOOL) + " " + args); }

// Runs a node binary that stands next to this test's executable (a rostest's gtest node)
// once, as `name`, with its private parameters as the caller set them on the master; at
// most `timeout_s`. A node refusing its parameters exits 2 with the reason on stderr.
inline ToolRun runSiblingNode(const std::string& binary, const std::string& name, int timeout_s = 30) {
  const std::filesystem::path node = std::filesystem::read_symlink("/proc/self/exe").parent_path() / binary;
  return runCommand("timeout " + std::to_string(timeout_s) + " " + node.string() + " __name:=" + name);
}

// A bad-input run as every subcommand must end it: exit 2, nothing on stdout, one line on
// stderr that holds `fragment`. (gtest assertions: include gtest before this header.)
inline void expectOneLineError(const ToolRun& run, const std::string& fragment) {
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;
  ASSERT_FALSE(run.err.empty());
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  EXPECT_NE(run.err.find(fragment), std::string::npos) << run.err;
}

}  // namespace room_reverb::test
