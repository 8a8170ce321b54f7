#pragma once
// A long-running room_reverb subcommand (`mushra serve`) started from a test: the tool
// runs in a child process whose first line on stdout is read (it names the address), and
// stop() ends it with SIGTERM as a user's Ctrl-C would, returning its exit status and the
// rest of its output. Header-only, as tool_run.h; POSIX.
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>

namespace room_reverb::test {

class ServedTool {
 public:
  // `args` as for runTool. The child's stderr goes to `stderr_file`.
  ServedTool(const std::string& args, const std::string& stderr_file) {
    // exec in the shell: the child's pid is the tool's, so SIGTERM reaches the tool. Made
    // before fork(): the child only calls what is safe between fork and exec.
    const std::string command = "exec " + std::string(ROOM_REVERB_TOOL) + " " + args + " 2>" + stderr_file;
    int out[2];
    if (::pipe(out) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      ::close(out[1]);
      ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(out[1]);
    out_ = out[0];
  }

  ~ServedTool() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) ::close(out_);
  }

  ServedTool(const ServedTool&) = delete;
  ServedTool& operator=(const ServedTool&) = delete;

  // The first line the tool printed (without the newline), or "" when it printed none
  // within `timeout_s` or ended first.
  std::string firstLine(double timeout_s = 10.0) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (output_.find('\n') == std::string::npos) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !readSome(static_cast<int>(left.count()))) return "";
    }
    return output_.substr(0, output_.find('\n'));
  }

  // The port of the "http://HOST:PORT/" in the first line; 0 when there is none.
  int port() {
    const std::string line = firstLine();
    const auto scheme = line.find("http://");
    if (scheme == std::string::npos) return 0;
    const auto colon = line.find(':', scheme + 7);
    return colon == std::string::npos ? 0 : std::atoi(line.c_str() + colon + 1);
  }

  // SIGTERM, then the exit status (-1 when the tool did not exit normally within 10 s).
  int stop() {
    if (pid_ <= 0) return -1;
    ::kill(pid_, SIGTERM);
    while (readSome(10000)) {
    }
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Everything the tool printed on stdout so far.
  const std::string& output() const { return output_; }

  // Reads what the tool printed within `timeout_ms` into output(); false when nothing
  // came. A test that makes the tool print a lot calls it meanwhile (from one thread),
  // or the tool blocks on a full pipe.
  bool readSome(int timeout_ms) {
    pollfd watched{out_, POLLIN, 0};
    if (::poll(&watched, 1, timeout_ms) <= 0) return false;
    char chunk[4096];
    const ssize_t n = ::read(out_, chunk, sizeof chunk);
    if (n <= 0) return false;
    output_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string output_;
};

}  // namespace room_reverb::test
