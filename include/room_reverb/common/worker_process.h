#pragma once
// A child process that answers framed messages on its standard input with framed messages
// on its standard output: how a job is handed to another program, on this machine or,
// through a command such as `ssh HOST room_reverb simulate-worker`, on another one.
//
// A frame is a 4-byte marker, a 1-byte kind and an 8-byte length, then the payload. The
// two ends are a Unix socket pair rather than pipes, so that writing to a worker that has
// died is an error to report (MSG_NOSIGNAL), not a SIGPIPE that kills the caller.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <sys/types.h>
#include <vector>

namespace room_reverb::core {

// A worker that did not start, died or answered with something that is not a frame. Not
// an InputError: the job may be fine, and a runner must not take it for a job's own
// refusal; a tool that started the worker from the user's command reports it as one.
class WorkerFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Frame {
  std::uint8_t kind = 0;
  std::vector<std::uint8_t> payload;
};

// Writes one frame; false when the other end has gone.
bool writeFrame(int fd, std::uint8_t kind, const std::vector<std::uint8_t>& payload);
// Reads one frame; nothing at a clean end of input (before a frame's first byte). Throws
// std::runtime_error for an end inside a frame or bytes that are not a frame.
std::optional<Frame> readFrame(int fd);

// The path of this process's executable (/proc/self/exe); InputError when it cannot be read.
std::string executablePath();
// `text` quoted for /bin/sh (in single quotes).
std::string shellQuoted(const std::string& text);

class WorkerProcess {
 public:
  // Starts `/bin/sh -c command` with its standard input and output on a socket to this
  // process (its standard error is this process's). Throws WorkerFailure if it cannot.
  explicit WorkerProcess(std::string command);
  // Closes the socket (a worker ends at the end of its input) and waits for the process.
  ~WorkerProcess();
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  // Sends one frame and waits for the reply. Throws WorkerFailure, naming the command
  // and how the process ended, when it has gone.
  Frame exchange(std::uint8_t kind, const std::vector<std::uint8_t>& payload);
  const std::string& command() const { return command_; }

 private:
  [[noreturn]] void failGone(const std::string& when);
  std::string command_;
  pid_t pid_ = -1;
  int fd_ = -1;
};

}  // namespace room_reverb::core
