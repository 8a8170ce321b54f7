// The HTTP server behind `mushra serve` (cpp-httplib under this project's limits), in
// this process with small limits and a short deadline, so that every limit is reached
// in milliseconds: what the handler sees of a request, and the status of each refusal.
#include <gtest/gtest.h>
#include <poll.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "http_client.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/http_server.h"

using namespace room_reverb::core;
using room_reverb::test::connectLoopback;
using room_reverb::test::readReply;
using room_reverb::test::sendBytes;
using room_reverb::test::sendRequest;

namespace {

// A server on a free port, serving from a thread for the test's lifetime. Its handler
// echoes what it was given; "/throw" throws.
class EchoServer {
 public:
  explicit EchoServer(HttpServerOptions options = smallLimits())
      : server_(options, [](const HttpRequest& request) {
          if (request.path == "/throw") throw std::runtime_error("the handler failed");
          return httpTextResponse(200, request.method + " " + request.path + " [" + request.body + "] agent=" +
                                           (request.headers.count("user-agent") ? request.headers.at("user-agent")
                                                                                : std::string("-")));
        }),
        serving_([this] { server_.serve(stop_); }) {}

  ~EchoServer() {
    stop_ = true;
    serving_.join();
  }

  int port() const { return server_.port(); }

  static HttpServerOptions smallLimits() {
    HttpServerOptions options;
    options.max_body_bytes = 1000;
    options.max_header_bytes = 2000;
    options.timeout_s = 1;
    options.max_connections = 32;
    return options;
  }

 private:
  std::atomic<bool> stop_{false};
  HttpServer server_;
  std::thread serving_;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST(HttpServer, TheHandlerSeesTheDecodedPathLowerCaseHeadersAndTheBody) {
  EchoServer server;
  const auto reply = sendRequest(server.port(),
                                 "POST /a%20b/c?x=1 HTTP/1.1\r\nUSER-AGENT: probe\r\nContent-Length: 5\r\n\r\nhello");
  EXPECT_EQ(reply.status, 200);
  EXPECT_EQ(reply.body, "POST /a b/c [hello] agent=probe\n");
  EXPECT_NE(reply.head.find("Connection: close"), std::string::npos) << reply.head;
  EXPECT_NE(reply.head.find("Cache-Control: no-store"), std::string::npos) << reply.head;
  // HEAD: the headers of the GET, no body.
  const auto head = room_reverb::test::httpGet(server.port(), "/x", "HEAD");
  EXPECT_EQ(head.status, 200);
  EXPECT_TRUE(head.body.empty());
  EXPECT_NE(head.head.find("Content-Length: 19"), std::string::npos) << head.head;  // "HEAD /x [] agent=-\n"
  EXPECT_NE(head.head.find("Accept-Ranges: none"), std::string::npos) << head.head;
  // A byte range is ignored: the whole answer, 200.
  const auto ranged = sendRequest(server.port(), "GET /x HTTP/1.1\r\nRange: bytes=5-1000000\r\n\r\n");
  EXPECT_EQ(ranged.status, 200);
  EXPECT_EQ(ranged.body, "GET /x [] agent=-\n");
  // A chunked body arrives decoded.
  const auto chunked =
      sendRequest(server.port(), "POST /c HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n3\r\nabc\r\n2\r\nde\r\n0\r\n\r\n");
  EXPECT_EQ(chunked.body, "POST /c [abcde] agent=-\n");
  // Expect: 100-continue: the interim answer, then the final one.
  const int s = connectLoopback(server.port());
  sendBytes(s, "POST /e HTTP/1.1\r\nContent-Length: 2\r\nExpect: 100-continue\r\n\r\n");
  char interim[64] = {};
  ASSERT_GT(::recv(s, interim, sizeof interim - 1, 0), 0);
  EXPECT_EQ(std::string(interim).rfind("HTTP/1.1 100 Continue", 0), 0u) << interim;
  sendBytes(s, "ok");
  EXPECT_EQ(readReply(s).body, "POST /e [ok] agent=-\n");
  ::close(s);
}

TEST(HttpServer, EachRefusalHasItsStatusAndAReason) {
  EchoServer server;
  const int port = server.port();
  const auto status = [port](const std::string& request) { return sendRequest(port, request).status; };
  // The body: over the limit by its header (nothing read), by its chunks, or unannounced.
  const auto large = sendRequest(port, "POST /x HTTP/1.1\r\nContent-Length: 1001\r\n\r\n");
  EXPECT_EQ(large.status, 413);
  EXPECT_NE(large.body.find("limit is 1000"), std::string::npos) << large.body;
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nContent-Length: 5000\r\nExpect: 100-continue\r\n\r\n"), 413);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n3e8\r\n" + std::string(1000, 'a') +
                   "\r\n1\r\nb\r\n0\r\n\r\n"),
            413);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\n\r\nbody"), 411);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nContent-Length: 4\r\nContent-Length: 40\r\n\r\nbody"), 400);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nContent-Length: 4\r\nTransfer-Encoding: chunked\r\n\r\nbody"), 400);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nContent-Length: 0x10\r\n\r\n"), 400);
  EXPECT_EQ(status("POST /x HTTP/1.1\r\nTransfer-Encoding: gzip\r\n\r\n"), 501);
  // The head: too large in its headers or its request line, malformed, or not HTTP.
  std::string headers;
  for (int i = 0; i < 30; ++i) headers += "X-Filler: " + std::string(90, 'f') + "\r\n";
  const auto big_head = sendRequest(port, "GET /x HTTP/1.1\r\n" + headers + "\r\n");
  EXPECT_EQ(big_head.status, 431);
  EXPECT_NE(big_head.body.find("2000 bytes"), std::string::npos) << big_head.body;
  EXPECT_EQ(status("GET /" + std::string(5000, 'a') + " HTTP/1.1\r\n\r\n"), 431);
  EXPECT_EQ(status("GET /a%zz HTTP/1.1\r\n\r\n"), 400);
  EXPECT_EQ(status("GET /a%00 HTTP/1.1\r\n\r\n"), 400);
  EXPECT_EQ(status("GET relative HTTP/1.1\r\n\r\n"), 400);
  EXPECT_EQ(status("BREW /pot HTTP/1.1\r\n\r\n"), 400);
  EXPECT_EQ(status("GET /x HTTP/2.0\r\n\r\n"), 400);
  const char tls_hello[] = "\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n";
  EXPECT_EQ(status(std::string(tls_hello, sizeof tls_hello - 1)), 400);  // HTTPS spoken to HTTP
  // The handler failing.
  const auto failed = room_reverb::test::httpGet(port, "/throw");
  EXPECT_EQ(failed.status, 500);
  EXPECT_NE(failed.body.find("the handler failed"), std::string::npos) << failed.body;
}

TEST(HttpServer, ARequestNotWholeByTheDeadlineIsCutWithoutHoldingTheOthers) {
  EchoServer server;  // a 1 s deadline
  const auto start = std::chrono::steady_clock::now();
  // A head sent a byte every 50 ms: every read succeeds quickly, the request never ends.
  std::atomic<int> trickled{0};
  std::thread trickler([&] {
    const int s = connectLoopback(server.port());
    const std::string head = "GET /slow HTTP/1.1\r\nX-Slow: " + std::string(200, 's');
    for (char c : head) {
      pollfd answered{s, POLLIN, 0};
      if (::poll(&answered, 1, 50) != 0 || !sendBytes(s, std::string(1, c)) || secondsSince(start) > 3.0) break;
    }
    trickled = readReply(s).status;
    ::close(s);
  });
  // A body that stops half-way.
  const int half = connectLoopback(server.port());
  sendBytes(half, "POST /half HTTP/1.1\r\nContent-Length: 100\r\n\r\nonly some");
  // Meanwhile others are answered at once.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  for (int i = 0; i < 10; ++i) {
    const auto request_start = std::chrono::steady_clock::now();
    EXPECT_EQ(room_reverb::test::httpGet(server.port(), "/quick").status, 200);
    EXPECT_LT(secondsSince(request_start), 0.5);
  }
  const auto half_reply = readReply(half);
  ::close(half);
  EXPECT_EQ(half_reply.status, 408);
  EXPECT_NE(half_reply.body.find("within 1 s"), std::string::npos) << half_reply.body;
  trickler.join();
  EXPECT_EQ(trickled, 408);
  EXPECT_LT(secondsSince(start), 3.0);
}

TEST(HttpServer, ConnectionsOverTheLimitAreAnswered503UntilOthersEnd) {
  HttpServerOptions four = EchoServer::smallLimits();
  four.max_connections = 4;
  EchoServer server(four);
  std::vector<int> idle;
  for (int i = 0; i < 4; ++i) idle.push_back(connectLoopback(server.port()));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // all four accepted
  const auto busy = room_reverb::test::httpGet(server.port(), "/x");
  EXPECT_EQ(busy.status, 503);
  EXPECT_NE(busy.body.find("too many connections"), std::string::npos) << busy.body;
  // The idle ones reach their deadline (1 s) and end; then there is room again.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(room_reverb::test::httpGet(server.port(), "/x").status, 200);
  for (int s : idle) ::close(s);
}

TEST(HttpServer, APortInUseOrAnUnknownHostIsAnInputError) {
  EchoServer first;
  HttpServerOptions same = EchoServer::smallLimits();
  same.port = first.port();
  EXPECT_THROW(
      {
        try {
          HttpServer second(same, [](const HttpRequest&) { return HttpResponse{}; });
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("already in use"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
  HttpServerOptions nowhere;
  nowhere.host = "no.such.host.invalid";
  EXPECT_THROW(HttpServer(nowhere, [](const HttpRequest&) { return HttpResponse{}; }), InputError);
  HttpServerOptions bad_port;
  bad_port.port = 70000;
  EXPECT_THROW(HttpServer(bad_port, [](const HttpRequest&) { return HttpResponse{}; }), InputError);
}

// A server stopped the moment it starts (before its accept loop runs, as a test or a
// Ctrl-C right after start may) ends at once instead of waiting in accept() for ever.
TEST(HttpServer, StoppedRightAfterStartingItEnds) {
  for (int i = 0; i < 200; ++i) {
    std::atomic<bool> stop{true};
    HttpServer server(EchoServer::smallLimits(), [](const HttpRequest&) { return HttpResponse{}; });
    server.serve(stop);
  }
}
