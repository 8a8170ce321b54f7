// room_reverb mushra serve: the test folder over HTTP on this machine. The server runs as
// a user starts it (a child process, port 0, stopped by SIGTERM); a small socket client
// sends it what a browser would, and what an attacker would: files, paths that try to
// leave the folder, results with and without the columns `mushra analyze` needs, bodies
// over the limit, requests that are not HTTP. And the pieces on their own: percent
// decoding, file names from listeners' names, content types.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <poll.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>
#include <nlohmann/json.hpp>
#include <sstream>

#include "room_reverb/common/text_file.h"
#include "room_reverb/common/http_server.h"
#include "room_reverb/listening/mushra_server.h"
#include "http_client.h"
#include "served_tool.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::sendRequest;
using Reply = room_reverb::test::HttpReply;
using room_reverb::test::runTool;
using room_reverb::test::ServedTool;
using room_reverb::test::tempPath;
namespace fs = std::filesystem;

namespace {

const char* kSecret = "the experimenter's secret";

// A test folder as `mushra make` leaves it, reduced to what the server reads: test.json
// (its scale and page ids), the page, an audio script; and a file beside the folder that
// must stay out of reach, also through a link inside the folder.
fs::path makeTestFolder(const std::string& name) {
    const fs::path parent = tempPath(name);
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
}

fs::path testFolder() {
  static const fs::path dir = makeTestFolder("serve_parent");
  return dir;
}

Reply get(int port, const std::string& path, const std::string& method = "GET") {
  return room_reverb::test::httpGet(port, path, method);
}

Reply post(int port, const std::string& path, const std::string& body) {
  return room_reverb::test::httpPost(port, path, body);
}

const std::string kHeader = "listener,page,room,content,attribute,condition,letter,score,duration_s\n";

std::string hexCount(std::size_t n) {
  char text[32];
  std::snprintf(text, sizeof text, "%zx", n);
  return text;
}

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
  // A chunked body (what a client sends when it streams) is read as any other...
  const std::string bo = kHeader + "Bo,room/speech/spatial,room,speech,spatial,rsao,A,4,3\n";
  const Reply chunked = sendRequest(port, "POST /results HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n" +
                                              hexCount(bo.size() - 20) + "\r\n" + bo.substr(0, bo.size() - 20) + "\r\n" +
                                              "14\r\n" + bo.substr(bo.size() - 20) + "\r\n0\r\n\r\n");
  ASSERT_EQ(chunked.status, 201) << chunked.body;
  EXPECT_EQ(readTextFile((testFolder() / nlohmann::json::parse(chunked.body).at("saved").get<std::string>()).string(),
                         "saved results"),
            bo);
  // ...and other encodings are refused.
  EXPECT_EQ(sendRequest(port, "POST /results HTTP/1.1\r\nTransfer-Encoding: gzip\r\n\r\nxyz").status, 501);
  EXPECT_EQ(sendRequest(port, "POST /results HTTP/1.1\r\nContent-Length: -4\r\n\r\n").status, 400);
  // A client that connects and says nothing does not hold up the others.
  const int idle = room_reverb::test::connectLoopback(port);
  ASSERT_GE(idle, 0);
  EXPECT_EQ(get(port, "/").status, 200);
  ::close(idle);
  EXPECT_EQ(savedResults().size(), 3u);  // and no half-written file beside them

  EXPECT_EQ(server.stop(), 0);
  EXPECT_NE(server.output().find("saved 2 ratings of Ann, the first to "), std::string::npos) << server.output();
  EXPECT_NE(server.output().find("saved 1 ratings of Bo to "), std::string::npos) << server.output();
  EXPECT_NE(server.output().find("stopped"), std::string::npos) << server.output();
}

// The load a lab's listening session puts on the server, and more: 50 listeners post
// their results at the same moment, 20 rounds over, while browsers fetch the page and
// four clients trickle requests they never finish. Every result is saved exactly once and
// whole, every listener gets its answer, the trickling clients are cut at the deadline
// (408) without holding up anyone, and the server still answers and stops when told.
TEST(MushraServe, FiftyListenersPostingAtOnceForTwentyRoundsAreEachSavedOnce) {
  constexpr int kListeners = 50, kRounds = 20, kTricklers = 4, kTimeoutS = 2;
  const fs::path folder = makeTestFolder("serve_load");
  ServedTool server("mushra serve " + folder.string() + " --port 0 --timeout " + std::to_string(kTimeoutS),
                    tempPath("serve_load_err.txt").string());
  const int port = server.port();
  ASSERT_GT(port, 0) << "first line: '" << server.firstLine() << "'";
  // One "saved ..." line per result: read as it comes, or the tool blocks on a full pipe.
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done) server.readSome(100);
  });

  using Clock = std::chrono::steady_clock;
  std::vector<int> trickled_status(kTricklers, 0);
  std::vector<double> trickled_s(kTricklers, 0.0);
  std::vector<std::thread> tricklers;
  for (int t = 0; t < kTricklers; ++t) {
    tricklers.emplace_back([&, t] {
      const auto start = Clock::now();
      const int s = room_reverb::test::connectLoopback(port);
      if (s < 0) return;
      const std::string request = "POST /results HTTP/1.1\r\nContent-Length: 400\r\n\r\n" + std::string(400, 'x');
      // A byte every 100 ms: each read of the server's succeeds long before any per-read
      // timeout, the whole request never arrives within the deadline.
      for (char c : request) {
        pollfd answered{s, POLLIN, 0};
        if (::poll(&answered, 1, 100) != 0 || !room_reverb::test::sendBytes(s, std::string(1, c))) break;
        if (Clock::now() - start > std::chrono::seconds(3 * kTimeoutS)) break;
      }
      trickled_status[t] = room_reverb::test::readReply(s).status;
      trickled_s[t] = std::chrono::duration<double>(Clock::now() - start).count();
      ::close(s);
    });
  }

  std::map<std::string, std::string> posted;  // saved file -> the body posted
  int refused = 0, page_failures = 0;
  for (int round = 0; round < kRounds; ++round) {
    std::vector<Reply> replies(kListeners);
    std::vector<std::string> bodies(kListeners);
    // The listeners wait at a gate, which opens once all are waiting: they post at once.
    std::mutex gate;
    std::condition_variable opened;
    int waiting = 0;
    std::vector<std::thread> listeners;
    for (int l = 0; l < kListeners; ++l) {
      bodies[l] = kHeader + "listener " + std::to_string(l) + ",room/speech/quality,room,speech,quality,reference,A,5," +
                  std::to_string(round) + "\nlistener " + std::to_string(l) +
                  ",room/speech/quality,room,speech,quality,rsao,B," + std::to_string((l + round) % 6) + "," +
                  std::to_string(round) + "\n";
      listeners.emplace_back([&, l] {
        {
          std::unique_lock<std::mutex> lock(gate);
          if (++waiting == kListeners) opened.notify_all();
          opened.wait(lock, [&] { return waiting == kListeners; });
        }
        replies[l] = post(port, "/results", bodies[l]);
      });
    }
    if (get(port, "/").status != 200) ++page_failures;
    for (std::thread& t : listeners) t.join();
    for (int l = 0; l < kListeners; ++l) {
      if (replies[l].status != 201) {
        ++refused;
        continue;
      }
      const std::string saved = nlohmann::json::parse(replies[l].body).at("saved");
      EXPECT_TRUE(posted.emplace(saved, bodies[l]).second) << saved << " given to two listeners";
    }
  }
  for (std::thread& t : tricklers) t.join();

  EXPECT_EQ(refused, 0);
  EXPECT_EQ(page_failures, 0);
  EXPECT_EQ(posted.size(), static_cast<std::size_t>(kListeners * kRounds));
  std::size_t files = 0, whole = 0;
  for (const auto& entry : fs::directory_iterator(folder / "results")) {
    ++files;
    const auto found = posted.find("results/" + entry.path().filename().string());
    if (found != posted.end() && readTextFile(entry.path().string(), "saved results") == found->second) ++whole;
  }
  EXPECT_EQ(files, posted.size()) << "every result saved once, no partial files";
  EXPECT_EQ(whole, posted.size()) << "each file holds exactly what its listener posted";
  for (int t = 0; t < kTricklers; ++t) {
    EXPECT_EQ(trickled_status[t], 408) << "trickling client " << t;
    EXPECT_GE(trickled_s[t], kTimeoutS - 0.2) << "trickling client " << t;
    EXPECT_LT(trickled_s[t], kTimeoutS + 3.0) << "trickling client " << t;
  }
  EXPECT_EQ(get(port, "/").status, 200);
  done = true;
  reader.join();
  EXPECT_EQ(server.stop(), 0);
  std::size_t lines = 0;
  for (std::size_t at = 0; (at = server.output().find("\nsaved 2 ratings of listener ", at)) != std::string::npos; ++at) {
    ++lines;
  }
  EXPECT_EQ(lines, posted.size());
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
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --port 4294967296"), "--port");
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --timeout 0"), "--timeout");
  expectOneLineError(runTool("mushra serve " + testFolder().string() + " --timeout soon"), "--timeout");
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
