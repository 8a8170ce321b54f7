#pragma once
// A raw HTTP client for the server tests: sends bytes as given (well-formed or not) over a
// loopback connection and reads the answer until the server closes. Header-only; POSIX.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace room_reverb::test {

struct HttpReply {
  int status = 0;    // 0: no answer (refused, reset, or not HTTP)
  std::string head;  // status line and headers
  std::string body;
};

// A connected socket to 127.0.0.1:`port` with a receive timeout; -1 when it cannot connect.
inline int connectLoopback(int port, int receive_timeout_s = 20) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  if (s < 0) return -1;
  timeval timeout{receive_timeout_s, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(s);
    return -1;
  }
  return s;
}

inline bool sendBytes(int s, const std::string& data) {
  for (std::size_t sent = 0; sent < data.size();) {
    const ssize_t n = ::send(s, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// Reads until the server closes, then parses the first answer (a "100 Continue" before
// it stays in `head`'s text only when asked for with `keep_interim`).
inline HttpReply readReply(int s, bool keep_interim = false) {
  std::string data;
  char chunk[4096];
  ssize_t n = 0;
  while ((n = ::recv(s, chunk, sizeof chunk, 0)) > 0) data.append(chunk, static_cast<std::size_t>(n));
  HttpReply reply;
  if (!keep_interim) {
    while (data.rfind("HTTP/1.1 100 ", 0) == 0 && data.find("\r\n\r\n") != std::string::npos) {
      data.erase(0, data.find("\r\n\r\n") + 4);
    }
  }
  const auto end = data.find("\r\n\r\n");
  if (data.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) return reply;
  reply.status = std::atoi(data.c_str() + 9);
  reply.head = data.substr(0, end);
  reply.body = data.substr(end + 4);
  return reply;
}

// Sends `request` as raw bytes and reads the answer until the server closes.
inline HttpReply sendRequest(int port, const std::string& request) {
  const int s = connectLoopback(port);
  if (s < 0) return {};
  sendBytes(s, request);
  HttpReply reply = readReply(s);
  ::close(s);
  return reply;
}

inline HttpReply httpGet(int port, const std::string& path, const std::string& method = "GET") {
  return sendRequest(port, method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
}

inline HttpReply httpPost(int port, const std::string& path, const std::string& body) {
  return sendRequest(port, "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: text/csv\r\nContent-Length: " +
                               std::to_string(body.size()) + "\r\n\r\n" + body);
}

}  // namespace room_reverb::test
