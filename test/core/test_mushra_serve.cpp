// room_reverb mushra serve: the test folder over HTTP on this machine. The server runs as
// a user starts it (a child process, port 0, stopped by SIGTERM); a small socket client
// sends it what a browser would, and what an attacker would: files, paths that try to
// leave the folder, results with and without the columns `mushra analyze` needs, bodies
// over the limit, requests that are not HTTP. And the pieces on their own: percent
// decoding, file names from listeners' names, content types.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "room_reverb/common/text_file.h"
#include "room_reverb/common/http_server.h"
#include "room_reverb/listening/mushra_server.h"
#include "served_tool.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::ServedTool;
using room_reverb::test::tempPath;
namespace fs = std::filesystem;

namespace {

const char* kSecret = "the experimenter's secret";

// A test folder as `mushra make` leaves it, reduced to what the server reads: test.json
// (its scale and page ids), the page, an audio script; and a file beside the folder that
// must stay out of reach, also through a link inside the folder.
fs::path testFolder() {
  static const fs::path dir = [] {
    const fs::path parent = tempPath("serve_parent");
    const fs::path d = parent / "test";
    fs::create_directories(d / "audio" / "room");
    const nlohmann::json test = {{"format", "room_reverb MUSHRA test"},
                                 {"scale", {{"name", "0-5"}, {"min", 0}, {"max", 5}, {"step", 1}}},
                                 {"pages", {{{"id", "room/speech/quality"}}, {{"id", "room/speech/spatial"}}}}};
    std::ofstream(d / "test.json") << test.dump(2);
    std::ofstream(d / "index.html") << "<!DOCTYPE html><title>test page</title>";
    std::ofstream(d / "audio" / "room" / "a b.js") << "window.x = 1;";
    std::ofstream(parent / "secret.txt") << kSecret;
    fs::create_symlink(parent / "secret.txt", d / "link.txt");
    return d;
  }();
  return dir;
}

struct Reply {
  int status = 0;
  std::string head;
  std::string body;
};

// Sends `request` as raw bytes and reads the answer until the server closes.
Reply sendRequest(int port, const std::string& request) {
  Reply reply;
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  timeval timeout{10, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(s);
    return reply;
  }
  std::size_t sent = 0;
  while (sent < request.size()) {
    const ssize_t n = ::send(s, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  std::string data;
  char chunk[4096];
  ssize_t n = 0;
  while ((n = ::recv(s, chunk, sizeof chunk, 0)) > 0) data.append(chunk, static_cast<std::size_t>(n));
  ::close(s);
  const auto end = data.find("\r\n\r\n");
  if (data.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) return reply;
  reply.status = std::atoi(data.c_str() + 9);
  reply.head = data.substr(0, end);
  reply.body = data.substr(end + 4);
  return reply;
}

Reply get(int port, const std::string& path, const std::string& method = "GET") {
  return sendRequest(port, method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
}

Reply post(int port, const std::string& path, const std::string& body) {
  return sendRequest(port, "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: text/csv\r\nContent-Length: " +
                            std::to_string(body.size()) + "\r\n\r\n" + body);
}

const std::string kHeader = "listener,page,room,content,attribute,condition,letter,score,duration_s\n";

std::vector<fs::path> savedResults() {
  std::vector<fs::path> files;
  if (fs::is_directory(testFolder() / "results")) {
    for (const auto& entry : fs::directory_iterator(testFolder() / "results")) files.push_back(entry.path());
  }
  return files;
}

}  // namespace

TEST(MushraServe, ServesTheFolderAndSavesCheckedResults) {
  ServedTool server("mushra serve " + testFolder().string() + " --port 0", tempPath("serve_err.txt").string());
  const int port = server.port();
  ASSERT_GT(port, 0) << "first line: '" << server.firstLine() << "'";
  EXPECT_NE(server.firstLine().find("http://127.0.0.1:" + std::to_string(port) + "/"), std::string::npos);

  // Files, with their types; "/" is the page.
  Reply page = get(port, "/");
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.head.find("Content-Type: text/html"), std::string::npos) << page.head;
  EXPECT_NE(page.body.find("test page"), std::string::npos);
  Reply script = get(port, "/audio/room/a%20b.js?v=1");
  EXPECT_EQ(script.status, 200);
  EXPECT_NE(script.head.find("Content-Type: text/javascript"), std::string::npos) << script.head;
  EXPECT_EQ(script.body, "window.x = 1;");
  Reply head = get(port, "/index.html", "HEAD");
  EXPECT_EQ(head.status, 200);
  EXPECT_TRUE(head.body.empty());
  EXPECT_EQ(get(port, "/no_such_file.js").status, 404);

  // Nothing outside the folder, however the path is spelled.
  for (const std::string path : {"/../secret.txt", "/%2e%2e/secret.txt", "/audio/../../secret.txt",
                                 "/audio/%2E%2E/%2E%2E/secret.txt", "/..%2fsecret.txt", "/link.txt",
                                 "/audio\\..\\..\\secret.txt"}) {
    const Reply r = get(port, path);
    EXPECT_TRUE(r.status == 403 || r.status == 404) << path << ": " << r.status;
    EXPECT_EQ(r.body.find(kSecret), std::string::npos) << path;
  }
  EXPECT_EQ(get(port, "/%zz").status, 400);
  EXPECT_EQ(get(port, "/a%00b").status, 400);

  // Results: saved when they read as `mushra analyze` reads them...
  const std::string valid = kHeader +
                            "\"Ann, the first\",room/speech/quality,room,speech,quality,reference,A,5,12.5\n"
                            "\"Ann, the first\",room/speech/quality,room,speech,quality,rsao,B,3,12.5\n";
  const Reply saved = post(port, "/results", valid);
  ASSERT_EQ(saved.status, 201) << saved.body;
  const auto answer = nlohmann::json::parse(saved.body);
  const std::string name = answer.at("saved");
  EXPECT_EQ(name.rfind("results/Ann_the_first_", 0), 0u) << name;
  EXPECT_EQ(readTextFile((testFolder() / name).string(), "saved results"), valid);
  // ...the same listener again gets a file of its own.
  const Reply again = post(port, "/results", valid);
  ASSERT_EQ(again.status, 201) << again.body;
  EXPECT_NE(nlohmann::json::parse(again.body).at("saved"), name);
  EXPECT_EQ(savedResults().size(), 2u);

  // ...and refused, with the reason, when they do not.
  const Reply missing = post(port, "/results", "listener,page,score\nAnn,room/speech/quality,5\n");
  EXPECT_EQ(missing.status, 400);
  EXPECT_NE(missing.body.find("missing columns"), std::string::npos) << missing.body;
  EXPECT_NE(missing.body.find("condition"), std::string::npos) << missing.body;
  const Reply outside = post(port, "/results", kHeader + "Ann,room/speech/quality,room,speech,quality,rsao,B,7,1\n");
  EXPECT_EQ(outside.status, 400);
  EXPECT_NE(outside.body.find("0-5"), std::string::npos) << outside.body;
  const Reply foreign = post(port, "/results", kHeader + "Ann,hall/music/quality,hall,music,quality,rsao,B,3,1\n");
  EXPECT_EQ(foreign.status, 400);
  EXPECT_NE(foreign.body.find("not a page of this test"), std::string::npos) << foreign.body;
  EXPECT_EQ(post(port, "/results", "").status, 400);
  // Over the limit: refused from the header, before any body is read.
  const Reply huge = sendRequest(port, "POST /results HTTP/1.1\r\nContent-Length: 20000000\r\n\r\n");
  EXPECT_EQ(huge.status, 413);
  EXPECT_EQ(savedResults().size(), 2u);

  // Other methods, and what is not HTTP.
  EXPECT_EQ(get(port, "/results").status, 405);
  EXPECT_EQ(sendRequest(port, "PUT /index.html HTTP/1.1\r\nContent-Length: 1\r\n\r\nx").status, 405);
  EXPECT_EQ(sendRequest(port, "hello\r\n\r\n").status, 400);
  EXPECT_EQ(sendRequest(port, "GET index.html HTTP/1.1\r\n\r\n").status, 400);
  EXPECT_EQ(sendRequest(port, "POST /results HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n").status, 501);
  EXPECT_EQ(sendRequest(port, "POST /results HTTP/1.1\r\nContent-Length: -4\r\n\r\n").status, 400);
  // A client that connects and says nothing does not hold up the others.
  const int idle = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(idle, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  EXPECT_EQ(get(port, "/").status, 200);
  ::close(idle);

  EXPECT_EQ(server.stop(), 0);
  EXPECT_NE(server.output().find("saved 2 ratings of Ann, the first to "), std::string::npos) << server.output();
  EXPECT_NE(server.output().find("stopped"), std::string::npos) << server.output();
}

TEST(MushraServe, BadFoldersAndPortsExitTwoWithOneLine) {
  const fs::path empty = tempPath("serve_not_a_test");
  fs::create_directories(empty);
  expectOneLineError(runTool("mushra serve " + empty.string() + " --port 0"), "no test.json");
  expectOneLineError(runTool("mushra serve " + tempPath("serve_nowhere").string()), "no such folder");
  const fs::path broken = tempPath("serve_broken");
  fs::create_directories(broken);
  std::ofstream(broken / "test.json") << "{\"pages\": ";
  expectOneLineError(runTool("mushra serve " + broken.string()), "not a room_reverb MUSHRA test");
  expectOneLineError(runTool("mushra serve"), "test folder");
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --port 70000"), "--port");
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --port http"), "--port");
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --host no.such.host.invalid"),
                     "no.such.host.invalid");

  // A port another program listens on.
  const int taken = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(taken, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(taken, 1), 0);
  socklen_t length = sizeof address;
  ::getsockname(taken, reinterpret_cast<sockaddr*>(&address), &length);
  const int port = ntohs(address.sin_port);
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --port " + std::to_string(port)), "in use");
  ::close(taken);
}

TEST(HttpServer, PercentDecodingRefusesMalformedEscapes) {
  std::string decoded;
  EXPECT_TRUE(percentDecodePath("/a%20b/%2E%2e/c+d", decoded));
  EXPECT_EQ(decoded, "/a b/../c+d");
  EXPECT_FALSE(percentDecodePath("/a%2", decoded));
  EXPECT_FALSE(percentDecodePath("/a%g0", decoded));
  EXPECT_FALSE(percentDecodePath("/a%00", decoded));
}

TEST(MushraServe, ListenerNamesBecomeSafeFileNames) {
  EXPECT_EQ(safeFileNamePart("Ann O'Nym"), "Ann_O_Nym");
  EXPECT_EQ(safeFileNamePart("../../etc/passwd"), ".._.._etc_passwd");
  EXPECT_EQ(safeFileNamePart(".."), "listener");
  EXPECT_EQ(safeFileNamePart(""), "listener");
  EXPECT_EQ(safeFileNamePart("Jürgen"), "J_rgen");
  EXPECT_EQ(safeFileNamePart(std::string(200, 'x')).size(), 60u);
  EXPECT_EQ(contentTypeOf("a/b.JS"), "text/javascript; charset=utf-8");
  EXPECT_EQ(contentTypeOf("pano.jpg"), "image/jpeg");
  EXPECT_EQ(contentTypeOf("stimulus.wav"), "audio/wav");
  EXPECT_EQ(contentTypeOf("noextension"), "application/octet-stream");
}
