#include "room_reverb/common/worker_process.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <stdexcept>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "room_reverb/common/error.h"

extern char** environ;

namespace room_reverb::core {
namespace {

constexpr std::uint32_t kFrameMarker = 0x52525746;  // "RRWF"
constexpr std::size_t kHeaderBytes = 4 + 1 + 8;
// No job or result comes near this; a larger length is corrupt input, not an allocation.
constexpr std::uint64_t kMaxPayloadBytes = std::uint64_t{1} << 34;

bool writeAll(int fd, const std::uint8_t* data, std::size_t size) {
  while (size > 0) {
    // send() on a socket (MSG_NOSIGNAL), write() on anything else (a pipe, a file).
    ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == ENOTSOCK) n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// Reads exactly `size` bytes; the count read before an end of input otherwise.
std::size_t readAll(int fd, std::uint8_t* data, std::size_t size) {
  std::size_t got = 0;
  while (got < size) {
    const ssize_t n = ::read(fd, data + got, size - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("reading a frame: ") + std::strerror(errno));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  return got;
}

}  // namespace

std::string executablePath() {
  std::vector<char> path(4096);
  const ssize_t n = ::readlink("/proc/self/exe", path.data(), path.size() - 1);
  if (n <= 0) throw InputError("cannot find this program's own path (/proc/self/exe)");
  return std::string(path.data(), static_cast<std::size_t>(n));
}

std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

bool writeFrame(int fd, std::uint8_t kind, const std::vector<std::uint8_t>& payload) {
  std::uint8_t header[kHeaderBytes];
  const std::uint64_t length = payload.size();
  std::memcpy(header, &kFrameMarker, 4);
  header[4] = kind;
  std::memcpy(header + 5, &length, 8);
  return writeAll(fd, header, kHeaderBytes) && writeAll(fd, payload.data(), payload.size());
}

std::optional<Frame> readFrame(int fd) {
  std::uint8_t header[kHeaderBytes];
  const std::size_t got = readAll(fd, header, kHeaderBytes);
  if (got == 0) return std::nullopt;
  if (got < kHeaderBytes) throw std::runtime_error("the input ended inside a frame's header");
  std::uint32_t marker;
  std::uint64_t length;
  std::memcpy(&marker, header, 4);
  std::memcpy(&length, header + 5, 8);
  if (marker != kFrameMarker) throw std::runtime_error("the input is not a stream of room_reverb frames");
  if (length > kMaxPayloadBytes) throw std::runtime_error("a frame claims " + std::to_string(length) + " bytes");
  Frame frame;
  frame.kind = header[4];
  frame.payload.resize(static_cast<std::size_t>(length));
  if (readAll(fd, frame.payload.data(), frame.payload.size()) != frame.payload.size()) {
    throw std::runtime_error("the input ended inside a frame");
  }
  return frame;
}

WorkerProcess::WorkerProcess(std::string command) : command_(std::move(command)) {
  int sockets[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sockets) != 0) {
    throw WorkerFailure(std::string("worker '") + command_ + "': socketpair: " + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, sockets[1], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, sockets[1], STDOUT_FILENO);
  const char* argv[] = {"/bin/sh", "-c", command_.c_str(), nullptr};
  const int rc = posix_spawn(&pid_, "/bin/sh", &actions, nullptr, const_cast<char* const*>(argv), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(sockets[1]);
  if (rc != 0) {
    ::close(sockets[0]);
    throw WorkerFailure(std::string("worker '") + command_ + "' did not start: " + std::strerror(rc));
  }
  fd_ = sockets[0];
}

WorkerProcess::~WorkerProcess() {
  if (fd_ >= 0) ::close(fd_);
  if (pid_ > 0) {
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

void WorkerProcess::failGone(const std::string& when) {
  ::close(fd_);
  fd_ = -1;
  int status = 0;
  std::string how = "ended";
  pid_t done = -1;
  while ((done = ::waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
  }
  if (done == pid_) {
    if (WIFEXITED(status)) how = "exited with status " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) how = "was killed by signal " + std::to_string(WTERMSIG(status));
  }
  pid_ = -1;
  throw WorkerFailure("worker '" + command_ + "' " + how + " " + when);
}

Frame WorkerProcess::exchange(std::uint8_t kind, const std::vector<std::uint8_t>& payload) {
  if (fd_ < 0) throw WorkerFailure("worker '" + command_ + "' has ended");
  if (!writeFrame(fd_, kind, payload)) failGone("before it took a job");
  std::optional<Frame> reply;
  try {
    reply = readFrame(fd_);
  } catch (const std::runtime_error& e) {
    failGone(std::string("while answering (") + e.what() + ")");
  }
  if (!reply) failGone("before it answered");
  return std::move(*reply);
}

}  // namespace room_reverb::core
