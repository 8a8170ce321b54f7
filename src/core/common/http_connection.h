#pragma once
// The two pieces of the HTTP server (http_server.h) that cpp-httplib lets a program
// replace, and that decide how it holds under load:
// - LimitedSocketStream: the socket as cpp-httplib reads and writes it, with a deadline
//   for the whole request and caps on its head and body. cpp-httplib's own stream has a
//   timeout per read only, so a client sending a byte every few seconds would keep its
//   connection (and thread) for ever, and it puts no bound on the number of header lines.
// - ThreadPerConnection: each connection on a thread of its own. cpp-httplib's default
//   pool has a fixed number of threads (8 here), which that many idle or slow clients
//   would fill, making everyone else wait.
#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

namespace room_reverb::core {

struct RequestLimits {
  std::chrono::steady_clock::time_point receive_deadline;  // the whole request by then
  int send_timeout_s = 10;        // for each write of the answer
  std::size_t max_head_bytes = 0;  // request line and headers, up to the blank line
  std::size_t max_body_bytes = 0;
};

class LimitedSocketStream : public httplib::Stream {
 public:
  LimitedSocketStream(int socket, const RequestLimits& limits);

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* data, std::size_t size) override;
  ssize_t write(const char* data, std::size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  int socket() const override { return socket_; }

  // What ended a read that failed; written once the head or the deadline is overrun.
  bool headTooLarge() const { return head_too_large_; }
  bool timedOut() const { return timed_out_; }
  std::size_t bytesReceived() const { return received_; }
  std::size_t bytesSent() const { return sent_; }

 private:
  // Waits for `events` on the socket until `deadline`; false when it passes first.
  bool waitFor(short events, std::chrono::steady_clock::time_point deadline) const;
  // Counts `count` received bytes against the head's cap (until the blank line that ends
  // it) and then against the head and body's together.
  bool withinCaps(const char* data, std::size_t count);

  int socket_;
  RequestLimits limits_;
  char buffer_[4096];  // cpp-httplib reads the head a byte at a time
  std::size_t buffered_begin_ = 0, buffered_end_ = 0;
  std::size_t received_ = 0, sent_ = 0;
  std::size_t head_bytes_ = 0;
  unsigned line_state_ = 0;  // how much of "\r\n\r\n" the last bytes matched
  bool head_done_ = false;
  bool head_too_large_ = false;
  mutable bool timed_out_ = false;
};

class ThreadPerConnection : public httplib::TaskQueue {
 public:
  ThreadPerConnection();
  void enqueue(std::function<void()> task) override;
  // Waits until every connection's thread has finished (their deadlines bound this).
  void shutdown() override;

 private:
  // Shared with the threads, which may still be releasing it after shutdown() returns.
  struct Running {
    std::mutex mutex;
    std::condition_variable finished;
    int count = 0;
  };
  std::shared_ptr<Running> running_;
};

}  // namespace room_reverb::core
