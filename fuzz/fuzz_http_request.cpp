// The request handling of the HTTP server behind `mushra serve` (http_server.h):
// cpp-httplib's parser under this project's limits, deadline stream and framing checks.
// The bytes go where a browser's would: over a loopback connection to a server started
// once per process. The handler answers from the parsed request (method, decoded path,
// headers, body), so everything the parser produced is read back; the answer must always
// arrive, a missing one is a finding.
#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <thread>

#include "fuzz_common.h"
#include "room_reverb/common/http_server.h"

namespace {

using room_reverb::core::HttpRequest;
using room_reverb::core::HttpResponse;

// Sends `size` bytes as one request over a loopback connection, ends it, and reads the
// answer until the server closes; traps when no answer ends within 20 s (longer than the
// server's own deadline: its answer must come first).
void exchange(int port, const uint8_t* data, std::size_t size) {
  const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (s < 0) return;  // out of descriptors: not the server's fault
  timeval timeout{};
  timeout.tv_sec = 20;
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(s);
    return;
  }
  // The server may answer (431, 413) and close before reading everything: a failed send
  // is expected then, hence MSG_NOSIGNAL and no check.
  std::size_t sent = 0;
  while (sent < size) {
    const ssize_t n = ::send(s, data + sent, size - sent, MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  ::shutdown(s, SHUT_WR);  // the end of the request: a half request is answered as malformed
  char buffer[4096];
  while (true) {
    const ssize_t n = ::recv(s, buffer, sizeof buffer, 0);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) __builtin_trap();  // the server hung on this request
      break;  // a reset after an early answer
    }
  }
  ::close(s);
}

int serverPort() {
  static const int port = [] {
    room_reverb::core::HttpServerOptions options;
    options.timeout_s = 5;  // the whole request: one that never ends gets its 408 within it
    options.max_body_bytes = 1u << 16;  // small limits, so the fuzzer reaches them
    options.max_header_bytes = 1u << 12;
    // Never destroyed: the serving thread runs until the process ends.
    auto* server = new room_reverb::core::HttpServer(options, [](const HttpRequest& request) {
      std::string echo = request.method + " " + request.path + " " + std::to_string(request.body.size());
      for (const auto& [name, value] : request.headers) echo += "\n" + name + ": " + value;
      return room_reverb::core::httpTextResponse(200, echo);
    });
    static std::atomic<bool> stop{false};
    std::thread([server] { server->serve(stop); }).detach();
    // One answered request first: the server's own threads (serving, accepting) are up
    // before the first input counts the process's threads.
    static const char kWarmUp[] = "GET / HTTP/1.1\r\n\r\n";
    exchange(server->port(), reinterpret_cast<const uint8_t*>(kWarmUp), sizeof kWarmUp - 1);
    return server->port();
  }();
  return port;
}

// The threads of this process. The server answers from a thread per connection, which
// still frees the request after the client has read the answer; the next input must not
// start before it is gone, or libFuzzer's per-input leak check sees the request's memory
// mid-release and reports a leak that is not one.
int threadCount() {
  DIR* tasks = ::opendir("/proc/self/task");
  if (!tasks) std::terminate();
  int count = 0;
  while (const dirent* entry = ::readdir(tasks)) {
    if (entry->d_name[0] != '.') ++count;
  }
  ::closedir(tasks);
  return count;
}

void waitForConnectionThreads(int baseline) {
  for (int waited_ms = 0; threadCount() > baseline; ++waited_ms) {
    if (waited_ms > 20000) __builtin_trap();  // a connection thread that never ends
    ::usleep(1000);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const int port = serverPort();
  const int baseline = threadCount();
  exchange(port, data, size);
  waitForConnectionThreads(baseline);
  // The path decoder on the raw bytes too, where the server's own checks do not filter.
  std::string decoded;
  room_reverb::core::percentDecodePath(room_reverb_fuzz::text(data, size), decoded);
  return 0;
}
