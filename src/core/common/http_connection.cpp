#include "http_connection.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

namespace room_reverb::core {
namespace {

using Clock = std::chrono::steady_clock;

void numericAddress(int socket, bool peer, std::string& ip, int& port) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  auto* raw = reinterpret_cast<sockaddr*>(&address);
  if ((peer ? ::getpeername(socket, raw, &length) : ::getsockname(socket, raw, &length)) != 0) return;
  char host[NI_MAXHOST], service[NI_MAXSERV];
  if (::getnameinfo(raw, length, host, sizeof host, service, sizeof service, NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
    return;
  }
  ip = host;
  port = std::atoi(service);
}

}  // namespace

LimitedSocketStream::LimitedSocketStream(int socket, const RequestLimits& limits) : socket_(socket), limits_(limits) {}

bool LimitedSocketStream::waitFor(short events, Clock::time_point deadline) const {
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd watched{socket_, events, 0};
    const int ready = ::poll(&watched, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready > 0) return true;  // readable, writable, or an error the next call reports
    if (ready < 0 && errno != EINTR) return false;
  }
}

bool LimitedSocketStream::is_readable() const {
  if (buffered_begin_ < buffered_end_) return true;
  if (waitFor(POLLIN, limits_.receive_deadline)) return true;
  timed_out_ = true;
  return false;
}

bool LimitedSocketStream::is_writable() const {
  return waitFor(POLLOUT, Clock::now() + std::chrono::seconds(limits_.send_timeout_s));
}

bool LimitedSocketStream::withinCaps(const char* data, std::size_t count) {
  static const char kHeadEnd[] = "\r\n\r\n";
  std::size_t i = 0;
  for (; i < count && !head_done_; ++i) {
    line_state_ = data[i] == kHeadEnd[line_state_] ? line_state_ + 1 : (data[i] == '\r' ? 1u : 0u);
    head_done_ = line_state_ == 4;
    if (++head_bytes_ > limits_.max_head_bytes) {
      head_too_large_ = true;
      return false;
    }
  }
  // The body's own cap applies to its decoded bytes (the server's content receiver); the
  // raw bytes after the head may add chunk framing, hence the head's cap as allowance.
  return received_ + count - head_bytes_ <= limits_.max_body_bytes + limits_.max_head_bytes;
}

ssize_t LimitedSocketStream::read(char* data, std::size_t size) {
  if (buffered_begin_ == buffered_end_) {
    if (!is_readable()) return -1;
    ssize_t n = 0;
    do {
      n = ::recv(socket_, buffer_, sizeof buffer_, 0);
    } while (n < 0 && errno == EINTR);
    if (n <= 0) return n;
    buffered_begin_ = 0;
    buffered_end_ = static_cast<std::size_t>(n);
  }
  const std::size_t count = std::min(size, buffered_end_ - buffered_begin_);
  const char* delivered = buffer_ + buffered_begin_;
  if (!withinCaps(delivered, count)) return -1;
  std::memcpy(data, delivered, count);
  buffered_begin_ += count;
  received_ += count;
  return static_cast<ssize_t>(count);
}

ssize_t LimitedSocketStream::write(const char* data, std::size_t size) {
  if (!is_writable()) return -1;
  ssize_t n = 0;
  // MSG_NOSIGNAL: a browser closing early is an error here, not a SIGPIPE that ends the server.
  do {
    n = ::send(socket_, data, size, MSG_NOSIGNAL);
  } while (n < 0 && errno == EINTR);
  if (n > 0) sent_ += static_cast<std::size_t>(n);
  return n;
}

void LimitedSocketStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  numericAddress(socket_, true, ip, port);
}

void LimitedSocketStream::get_local_ip_and_port(std::string& ip, int& port) const {
  numericAddress(socket_, false, ip, port);
}

ThreadPerConnection::ThreadPerConnection() : running_(std::make_shared<Running>()) {}

void ThreadPerConnection::enqueue(std::function<void()> task) {
  {
    std::lock_guard<std::mutex> lock(running_->mutex);
    ++running_->count;
  }
  std::thread([running = running_, task = std::move(task)] {
    task();
    std::lock_guard<std::mutex> lock(running->mutex);
    --running->count;
    running->finished.notify_all();
  }).detach();
}

void ThreadPerConnection::shutdown() {
  std::unique_lock<std::mutex> lock(running_->mutex);
  running_->finished.wait(lock, [this] { return running_->count == 0; });
}

}  // namespace room_reverb::core
