#include "room_reverb/common/http_server.h"

#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <thread>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// send() until everything is out; MSG_NOSIGNAL so that a browser closing early is an
// error here, not a SIGPIPE that ends the server.
bool sendAll(int socket, const std::string& data) {
  std::size_t sent = 0;
  while (sent < data.size()) {
    const ssize_t n = ::send(socket, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

void sendResponse(int socket, const HttpResponse& response, bool with_body) {
  std::string head = "HTTP/1.1 " + std::to_string(response.status) + " " + httpReasonPhrase(response.status) +
                     "\r\nContent-Type: " + response.content_type +
                     "\r\nContent-Length: " + std::to_string(response.body.size()) +
                     // no-store: a test made again in the same folder must not be served from a cache
                     "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n";
  if (with_body) head += response.body;
  sendAll(socket, head);
}

// Reads more bytes into `buffer`; false at the end of the stream, an error or the timeout.
bool receiveMore(int socket, std::string& buffer) {
  char chunk[16384];
  while (true) {
    const ssize_t n = ::recv(socket, chunk, sizeof chunk, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    buffer.append(chunk, static_cast<std::size_t>(n));
    return true;
  }
}

void setTimeout(int socket, int option, int seconds) {
  timeval timeout{};
  timeout.tv_sec = seconds;
  ::setsockopt(socket, SOL_SOCKET, option, &timeout, sizeof timeout);
}

// Parses the request line and the headers (everything before the blank line). False for
// a malformed head.
bool parseHead(const std::string& head, HttpRequest& request) {
  std::size_t line_end = head.find("\r\n");
  const std::string request_line = head.substr(0, line_end);
  const auto first_space = request_line.find(' ');
  const auto last_space = request_line.rfind(' ');
  if (first_space == std::string::npos || last_space == first_space) return false;
  request.method = request_line.substr(0, first_space);
  request.target = request_line.substr(first_space + 1, last_space - first_space - 1);
  const std::string version = request_line.substr(last_space + 1);
  if (request.method.empty() || request.target.empty() || version.rfind("HTTP/1.", 0) != 0) return false;
  while (line_end != std::string::npos && line_end + 2 < head.size()) {
    const std::size_t start = line_end + 2;
    line_end = head.find("\r\n", start);
    const std::string line = head.substr(start, line_end == std::string::npos ? std::string::npos : line_end - start);
    const auto colon = line.find(':');
    if (colon == std::string::npos || colon == 0) return false;
    request.headers[lowerCase(trimmed(line.substr(0, colon)))] = trimmed(line.substr(colon + 1));
  }
  return true;
}

}  // namespace

std::string httpReasonPhrase(int status) {
  switch (status) {
    case 100: return "Continue";
    case 200: return "OK";
    case 201: return "Created";
    case 400: return "Bad Request";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Content Too Large";
    case 415: return "Unsupported Media Type";
    case 431: return "Request Header Fields Too Large";
    case 500: return "Internal Server Error";
    case 501: return "Not Implemented";
    case 503: return "Service Unavailable";
    default: return "Status";
  }
}

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

HttpServer::HttpServer(const HttpServerOptions& options, Handler handler)
    : options_(options), handler_(std::move(handler)) {
  const std::string where = options_.host + ":" + std::to_string(options_.port);
  if (options_.port < 0 || options_.port > 65535) {
    throw InputError("port " + std::to_string(options_.port) + " is not a TCP port (0..65535; 0 picks a free one)");
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* addresses = nullptr;
  const int resolved = ::getaddrinfo(options_.host.c_str(), std::to_string(options_.port).c_str(), &hints, &addresses);
  if (resolved != 0) throw InputError(options_.host + ": not an address of this machine (" + gai_strerror(resolved) + ")");
  int bind_error = 0;
  for (addrinfo* a = addresses; a && listener_ < 0; a = a->ai_next) {
    const int s = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (s < 0) {
      bind_error = errno;
      continue;
    }
    // A restarted server may take its port back while old connections linger in
    // TIME_WAIT; a port another program listens on stays refused.
    const int yes = 1;
    ::setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(s, a->ai_addr, a->ai_addrlen) == 0 && ::listen(s, 64) == 0) {
      listener_ = s;
    } else {
      bind_error = errno;
      ::close(s);
    }
  }
  ::freeaddrinfo(addresses);
  if (listener_ < 0) {
    if (bind_error == EADDRINUSE) throw InputError(where + ": the port is already in use by another program");
    if (bind_error == EACCES) throw InputError(where + ": permission denied (ports below 1024 need privileges)");
    if (bind_error == EADDRNOTAVAIL) throw InputError(where + ": " + options_.host + " is not an address of this machine");
    throw InputError(where + ": cannot listen: " + std::strerror(bind_error));
  }
  sockaddr_storage bound{};
  socklen_t length = sizeof bound;
  ::getsockname(listener_, reinterpret_cast<sockaddr*>(&bound), &length);
  port_ = ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                            : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
}

HttpServer::~HttpServer() {
  if (listener_ >= 0) ::close(listener_);
}

void HttpServer::serve(const std::atomic<bool>& stop) {
  while (!stop) {
    pollfd watched{listener_, POLLIN, 0};
    const int ready = ::poll(&watched, 1, 200);
    if (ready <= 0) continue;  // the timeout, or a signal: look at `stop` again
    const int connection = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
    if (connection < 0) continue;
    if (active_ >= options_.max_connections) {
      sendResponse(connection, httpTextResponse(503, "too many connections at once; try again"), true);
      ::close(connection);
      continue;
    }
    ++active_;
    std::thread([this, connection] {
      handleConnection(connection);
      --active_;  // last: the server may be gone once this reaches zero
    }).detach();
  }
  // The connections' own timeouts bound this wait.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2 * options_.timeout_s + 1);
  while (active_ > 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

void HttpServer::handleConnection(int socket) {
  setTimeout(socket, SO_RCVTIMEO, options_.timeout_s);
  setTimeout(socket, SO_SNDTIMEO, options_.timeout_s);
  const auto answer = [socket](const HttpResponse& response, bool with_body = true) {
    sendResponse(socket, response, with_body);
    ::shutdown(socket, SHUT_WR);
    ::close(socket);
  };
  std::string data;
  std::size_t head_end = std::string::npos;
  while ((head_end = data.find("\r\n\r\n")) == std::string::npos) {
    if (data.size() > options_.max_header_bytes) return answer(httpTextResponse(431, "request head too large"));
    if (!receiveMore(socket, data)) {
      // Nothing sent (an unused speculative connection) or a half request: nobody to answer.
      ::close(socket);
      return;
    }
  }
  HttpRequest request;
  if (!parseHead(data.substr(0, head_end), request)) return answer(httpTextResponse(400, "malformed request"));
  const std::string path = request.target.substr(0, request.target.find('?'));
  if (path.empty() || path[0] != '/' || !percentDecodePath(path, request.path)) {
    return answer(httpTextResponse(400, "malformed path"));
  }
  if (request.headers.count("transfer-encoding")) {
    return answer(httpTextResponse(501, "chunked request bodies are not supported; send Content-Length"));
  }
  std::size_t length = 0;
  if (request.headers.count("content-length")) {
    const std::string& text = request.headers["content-length"];
    if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos) {
      return answer(httpTextResponse(400, "malformed Content-Length"));
    }
    length = std::stoull(text);
    if (length > options_.max_body_bytes) {
      return answer(httpTextResponse(413, "request body of " + text + " bytes; the limit is " +
                                              std::to_string(options_.max_body_bytes)));
    }
  }
  if (length > 0 && lowerCase(request.headers["expect"]) == "100-continue") {
    sendAll(socket, "HTTP/1.1 100 Continue\r\n\r\n");
  }
  request.body = data.substr(head_end + 4);
  while (request.body.size() < length) {
    if (!receiveMore(socket, request.body)) return answer(httpTextResponse(400, "request body shorter than its Content-Length"));
  }
  request.body.resize(length);
  HttpResponse response;
  try {
    response = handler_(request);
  } catch (const std::exception& e) {
    response = httpTextResponse(500, std::string("internal error: ") + e.what());
  }
  answer(response, request.method != "HEAD");
}

}  // namespace room_reverb::core
