#pragma once
// The HTTP/1.1 server behind `room_reverb mushra serve`, on Debian's cpp-httplib (the
// request parsing, chunked bodies, Expect: 100-continue, HEAD): enough for a listening
// test on one machine or a lab's network. What this layer adds is what a server that
// collects results must hold under load: a thread per connection (up to a limit), so that a slow or idle
// client never holds up the others; a deadline for the whole request, so that a client
// trickling bytes cannot keep its thread; caps on the head and the body; one request per
// connection (the answer says Connection: close). What a request means is up to a
// handler; the server only parses and answers.
#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>

namespace room_reverb::core {

struct HttpRequest {
  std::string method;   // "GET"
  std::string target;   // as sent, without a fragment: "/audio/a%20b.js?x=1"
  std::string path;     // the target's path, percent-decoded: "/audio/a b.js"
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

// The answer for a status with a plain-text body of `message` and a newline.
HttpResponse httpTextResponse(int status, const std::string& message);

// Percent-decoding of a URL path; false for a malformed escape or an encoded NUL (which
// cpp-httplib's own decoding lets through as text or as a NUL byte).
bool percentDecodePath(const std::string& encoded, std::string& decoded);

struct HttpServerOptions {
  std::string host = "127.0.0.1";  // numeric address or name; "0.0.0.0" for every interface
  int port = 0;                    // 0: a free port, chosen by the system
  std::size_t max_body_bytes = 10u << 20;   // more: 413, refused before the body is read
  std::size_t max_header_bytes = 64u << 10;  // request line and headers; more: 431
  // The whole request (head and body) must arrive within this time after the connection
  // opens (else 408); each part of the answer must be taken by the client within it.
  int timeout_s = 10;
  // At once, counting those still closing; more are answered 503. A browser opens several
  // connections to load a page, and a lab may have 50 listeners.
  int max_connections = 512;
};

class HttpServer {
 public:
  using Handler = std::function<HttpResponse(const HttpRequest&)>;

  // Binds and listens. InputError for a port outside 0..65535, a host that does not
  // resolve, or an address that cannot be bound (the port in use, a privileged port).
  HttpServer(const HttpServerOptions& options, Handler handler);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const;  // the bound port (the chosen one for port 0)
  const std::string& host() const;

  // Accepts connections until `stop` is true (checked at least every 200 ms, so a signal
  // handler may set it), then waits for the requests under way to be answered. The
  // handler runs on the connections' threads: it must be thread-safe.
  void serve(const std::atomic<bool>& stop);

 private:
  class Implementation;
  std::unique_ptr<Implementation> implementation_;
};

}  // namespace room_reverb::core
