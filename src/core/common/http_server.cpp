#include "room_reverb/common/http_server.h"

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <optional>
#include <thread>

#include "http_connection.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

using Clock = std::chrono::steady_clock;

// POST paths are matched by cpp-httplib with std::regex, whose matcher recurses once per
// character; the test's paths are short, and a long one is refused before the match.
constexpr std::size_t kMaxPostPathBytes = 1024;

// The connection a thread serves, for the error handler, which cpp-httplib calls with
// the request and the answer only.
thread_local const LimitedSocketStream* current_stream = nullptr;

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

// The reason phrases of the failures this layer answers or explains itself (cpp-httplib's
// table is private to its library).
const char* reasonPhrase(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Content Too Large";
    case 414: return "URI Too Long";
    case 416: return "Range Not Satisfiable";
    case 431: return "Request Header Fields Too Large";
    case 500: return "Internal Server Error";
    case 501: return "Not Implemented";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

void writeBareResponse(LimitedSocketStream& stream, const HttpResponse& response) {
  const std::string text = "HTTP/1.1 " + std::to_string(response.status) + " " + reasonPhrase(response.status) +
                           "\r\nContent-Type: " + response.content_type +
                           "\r\nContent-Length: " + std::to_string(response.body.size()) +
                           "\r\nConnection: close\r\n\r\n" + response.body;
  for (std::size_t sent = 0; sent < text.size();) {
    const ssize_t n = stream.write(text.data() + sent, text.size() - sent);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

// Ends the connection so that the answer reaches the client even when it is still
// sending (a body refused unread): closing a socket with unread input resets it, and a
// reset may overtake the answer. So: no more sending, then read and drop what still
// comes, for a bounded time, until the client closes.
void lingeringClose(int socket) {
  ::shutdown(socket, SHUT_WR);
  const auto deadline = Clock::now() + std::chrono::seconds(2);
  char discard[4096];
  timeval poll_step{0, 200000};
  ::setsockopt(socket, SOL_SOCKET, SO_RCVTIMEO, &poll_step, sizeof poll_step);
  std::size_t drained = 0;
  while (Clock::now() < deadline && drained < (1u << 20)) {
    const ssize_t n = ::recv(socket, discard, sizeof discard, 0);
    if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK)) break;
    if (n > 0) drained += static_cast<std::size_t>(n);
  }
  ::close(socket);
}

// What a bind of `host`:`port` fails with (errno), for the one-line error: cpp-httplib
// reports only that it failed.
int bindError(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* addresses = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &addresses) != 0) return EADDRNOTAVAIL;
  int error = 0;
  for (addrinfo* a = addresses; a; a = a->ai_next) {
    const int s = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (s < 0) {
      error = errno;
      continue;
    }
    const int yes = 1;
    ::setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    error = ::bind(s, a->ai_addr, a->ai_addrlen) == 0 && ::listen(s, 1) == 0 ? 0 : errno;
    ::close(s);
    if (error == 0) break;
  }
  ::freeaddrinfo(addresses);
  return error;
}

}  // namespace

HttpResponse httpTextResponse(int status, const std::string& message) {
  return {status, "text/plain; charset=utf-8", message + "\n"};
}

bool percentDecodePath(const std::string& encoded, std::string& decoded) {
  decoded.clear();
  for (std::size_t i = 0; i < encoded.size(); ++i) {
    if (encoded[i] != '%') {
      decoded += encoded[i];
      continue;
    }
    if (i + 2 >= encoded.size()) return false;
    const int high = hexValue(encoded[i + 1]), low = hexValue(encoded[i + 2]);
    if (high < 0 || low < 0 || (high == 0 && low == 0)) return false;
    decoded += static_cast<char>(high * 16 + low);
    i += 2;
  }
  return true;
}

class HttpServer::Implementation : public httplib::Server {
 public:
  Implementation(const HttpServerOptions& options, HttpServer::Handler handler);

  HttpServerOptions options;
  int bound_port = 0;

  void widenBacklog() { ::listen(svr_sock_, SOMAXCONN); }

 private:
  // Replaces cpp-httplib's connection loop (a timeout per read, keep-alive): one request,
  // under the limits, on a stream that enforces them.
  bool process_and_close_socket(int socket) override;

  // The request's framing, checked before any body is read; an answer when it is refused.
  std::optional<HttpResponse> refusedFraming(const httplib::Request& request) const;
  // The handler's answer to `request` with `body`, its exceptions turned into a 500.
  void answer(const httplib::Request& request, std::string body, httplib::Response& response) const;

  HttpServer::Handler handler_;
  std::atomic<int> active_{0};
};

HttpServer::Implementation::Implementation(const HttpServerOptions& server_options, HttpServer::Handler handler)
    : options(server_options), handler_(std::move(handler)) {
  new_task_queue = [] { return new ThreadPerConnection(); };
  // SO_REUSEADDR only: a restarted server may take its port back while old connections
  // linger in TIME_WAIT. cpp-httplib's default, SO_REUSEPORT, would let a second server
  // share a port another one listens on.
  set_socket_options([](int socket) {
    const int yes = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  set_read_timeout(options.timeout_s);
  set_write_timeout(options.timeout_s);
  set_payload_max_length(options.max_body_bytes);
  // no-store: a test made again in the same folder must not be served from a cache.
  // Accept-Ranges: none, since ranges are ignored (process_and_close_socket); cpp-httplib
  // would announce "bytes" to a HEAD.
  set_default_headers({{"Cache-Control", "no-store"}, {"X-Content-Type-Options", "nosniff"}, {"Accept-Ranges", "none"}});
  // A body over the limit is refused before the client sends it.
  set_expect_100_continue_handler([this](const httplib::Request& request, httplib::Response& response) {
    if (const auto refusal = refusedFraming(request)) {
      response.status = refusal->status;
      response.set_content(refusal->body, refusal->content_type.c_str());
      return refusal->status;
    }
    return 100;
  });
  set_pre_routing_handler([this](const httplib::Request& request, httplib::Response& response) {
    if (const auto refusal = refusedFraming(request)) {
      response.status = refusal->status;
      response.set_content(refusal->body, refusal->content_type.c_str());
      return HandlerResponse::Handled;
    }
    if (request.method == "POST") return HandlerResponse::Unhandled;  // on to the body's reader
    // Any other method is answered without reading a body it may have sent.
    answer(request, "", response);
    return HandlerResponse::Handled;
  });
  Post("[\\s\\S]*", [this](const httplib::Request& request, httplib::Response& response,
                           const httplib::ContentReader& read_body) {
    std::string body;
    bool too_large = false;
    const bool complete = read_body([&](const char* data, std::size_t size) {
      too_large = body.size() + size > options.max_body_bytes;
      if (!too_large) body.append(data, size);
      return !too_large;
    });
    if (too_large) {
      const HttpResponse refusal = httpTextResponse(413, "request body over the limit of " +
                                                             std::to_string(options.max_body_bytes) + " bytes");
      response.status = refusal.status;
      response.set_content(refusal.body, refusal.content_type.c_str());
    } else if (!complete) {
      response.status = 400;  // the error handler says why
    } else {
      answer(request, std::move(body), response);
    }
  });
  // The failures cpp-httplib answers by itself (a malformed head, a body cut short) get a
  // reason in their body, and the status of what really happened on this connection.
  set_error_handler(HandlerWithResponse([this](const httplib::Request&, httplib::Response& response) {
    if (current_stream && current_stream->timedOut()) {
      response.status = 408;
      response.set_content("request not received within " + std::to_string(options.timeout_s) + " s\n",
                           "text/plain; charset=utf-8");
    } else if (current_stream && current_stream->headTooLarge()) {
      response.status = 431;
      response.set_content("request head over the limit of " + std::to_string(options.max_header_bytes) +
                               " bytes\n",
                           "text/plain; charset=utf-8");
    } else if (response.body.empty()) {
      response.set_content(std::string(reasonPhrase(response.status)) + "\n", "text/plain; charset=utf-8");
    }
    // Unhandled: no byte ranges applied to an error's body.
    return HandlerResponse::Unhandled;
  }));
}

std::optional<HttpResponse> HttpServer::Implementation::refusedFraming(const httplib::Request& request) const {
  std::string path;
  const std::string target_path = request.target.substr(0, request.target.find('?'));
  if (target_path.empty() || target_path[0] != '/' || !percentDecodePath(target_path, path)) {
    return httpTextResponse(400, "malformed path");
  }
  const std::size_t lengths = request.get_header_value_count("Content-Length");
  const bool chunked = request.has_header("Transfer-Encoding");
  if (lengths > 1 || (lengths == 1 && chunked)) {
    return httpTextResponse(400, "a request names its body's length once, by Content-Length or chunked encoding");
  }
  if (chunked && lowerCase(request.get_header_value("Transfer-Encoding")) != "chunked") {
    return httpTextResponse(501, "transfer encodings other than chunked are not supported");
  }
  if (lengths == 1) {
    const std::string text = request.get_header_value("Content-Length");
    if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
      return httpTextResponse(400, "malformed Content-Length");
    }
    if (std::stoull(text) > options.max_body_bytes) {
      return httpTextResponse(413, "request body of " + text + " bytes; the limit is " +
                                       std::to_string(options.max_body_bytes));
    }
  }
  if (request.method == "POST") {
    if (lengths == 0 && !chunked) return httpTextResponse(411, "a POST needs a Content-Length");
    if (path.size() > kMaxPostPathBytes) return httpTextResponse(414, "path too long");
  }
  return std::nullopt;
}

void HttpServer::Implementation::answer(const httplib::Request& request, std::string body,
                                        httplib::Response& response) const {
  HttpRequest mine;
  mine.method = request.method;
  mine.target = request.target;
  percentDecodePath(request.target.substr(0, request.target.find('?')), mine.path);  // checked by refusedFraming
  for (const auto& [name, value] : request.headers) {
    // cpp-httplib adds the connection's addresses as headers; they are not the client's.
    if (name == "REMOTE_ADDR" || name == "REMOTE_PORT" || name == "LOCAL_ADDR" || name == "LOCAL_PORT") continue;
    mine.headers.emplace(lowerCase(name), value);
  }
  mine.body = std::move(body);
  HttpResponse reply;
  try {
    reply = handler_(mine);
  } catch (const std::exception& e) {
    reply = httpTextResponse(500, std::string("internal error: ") + e.what());
  }
  response.status = reply.status;
  response.set_content(std::move(reply.body), reply.content_type.c_str());
}

bool HttpServer::Implementation::process_and_close_socket(int socket) {
  const int active = ++active_;
  const RequestLimits limits{Clock::now() + std::chrono::seconds(options.timeout_s), options.timeout_s,
                             options.max_header_bytes, options.max_body_bytes};
  LimitedSocketStream stream(socket, limits);
  bool answered = false;
  if (active > options.max_connections) {
    writeBareResponse(stream, httpTextResponse(503, "too many connections at once; try again"));
  } else {
    current_stream = &stream;
    bool connection_closed = false;
    // Byte ranges are ignored (the whole file is sent, as RFC 9110 allows): the test's
    // files are small, and cpp-httplib 0.11 trusts ranges past a body's end.
    answered = process_request(stream, true, connection_closed, [](httplib::Request& request) { request.ranges.clear(); });
    current_stream = nullptr;
    // cpp-httplib answers nothing when the request line itself fails; an unused
    // (speculative) connection gets nothing either.
    if (stream.bytesSent() == 0 && stream.bytesReceived() > 0) {
      writeBareResponse(stream, stream.headTooLarge() ? httpTextResponse(431, "request head too large")
                                : stream.timedOut()   ? httpTextResponse(408, "request not received in time")
                                                      : httpTextResponse(400, "malformed request"));
    }
  }
  // A connection that got no answer has nothing to protect from a reset.
  if (stream.bytesSent() > 0) {
    lingeringClose(socket);
  } else {
    ::close(socket);
  }
  --active_;
  return answered;
}

HttpServer::HttpServer(const HttpServerOptions& options, Handler handler)
    : implementation_(std::make_unique<Implementation>(options, std::move(handler))) {
  const std::string where = options.host + ":" + std::to_string(options.port);
  if (options.port < 0 || options.port > 65535) {
    throw InputError("port " + std::to_string(options.port) + " is not a TCP port (0..65535; 0 picks a free one)");
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* addresses = nullptr;
  const int resolved = ::getaddrinfo(options.host.c_str(), nullptr, &hints, &addresses);
  if (resolved != 0) throw InputError(options.host + ": not an address of this machine (" + gai_strerror(resolved) + ")");
  ::freeaddrinfo(addresses);
  Implementation& server = *implementation_;
  if (options.port == 0) {
    server.bound_port = server.bind_to_any_port(options.host);
  } else if (server.bind_to_port(options.host, options.port)) {
    server.bound_port = options.port;
  }
  // cpp-httplib listens with a backlog of 5 (compiled into Debian's library): a burst of
  // listeners finishing at once overflows it, and each dropped connection waits a SYN
  // retransmission (1 s, then 3 s) — 50 posts at once took 2–3 s a round instead of
  // milliseconds. listen() again on the bound socket sets the system's maximum.
  if (server.bound_port > 0) server.widenBacklog();
  if (server.bound_port <= 0) {
    const int error = bindError(options.host, options.port);
    if (error == EADDRINUSE) throw InputError(where + ": the port is already in use by another program");
    if (error == EACCES) throw InputError(where + ": permission denied (ports below 1024 need privileges)");
    if (error == EADDRNOTAVAIL) throw InputError(where + ": " + options.host + " is not an address of this machine");
    throw InputError(where + ": cannot listen" + (error ? std::string(": ") + std::strerror(error) : std::string()));
  }
}

HttpServer::~HttpServer() = default;

int HttpServer::port() const { return implementation_->bound_port; }

const std::string& HttpServer::host() const { return implementation_->options.host; }

void HttpServer::serve(const std::atomic<bool>& stop) {
  Implementation& server = *implementation_;
  // cpp-httplib's accept loop runs until stop() closes the listening socket; then its
  // task queue waits for the connections under way, whose deadlines bound the wait.
  std::atomic<bool> finished{false};
  std::thread accepting([&server, &finished] {
    server.listen_after_bind();
    finished = true;
  });
  while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  // stop() closes the listening socket only once the accept loop has started (it checks
  // is_running()), and must not be called twice (it asserts the socket is open): a server
  // told to stop right after it started would otherwise wait in accept() for ever.
  while (!finished) {
    if (server.is_running()) {
      server.stop();
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  accepting.join();
}

}  // namespace room_reverb::core
