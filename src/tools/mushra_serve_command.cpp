// room_reverb mushra serve: the test page of a MUSHRA test over HTTP on this machine,
// for browsers that should post their results to the experimenter
// instead of leaving a download on the listener's computer.
#include <signal.h>

#include <atomic>
#include <iostream>
#include <mutex>

#include "arguments.h"
#include "command.h"
#include "mushra_steps.h"
#include "room_reverb/common/http_server.h"
#include "room_reverb/listening/mushra_server.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

// Set by SIGINT/SIGTERM; the server looks at it between connections. A lock-free atomic,
// so that the handler may set it.
std::atomic<bool> stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free);

void requestStop(int) { stop_requested = true; }

void installStopHandlers() {
  struct sigaction action {};
  action.sa_handler = requestStop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

const char* const kMushraServeHelp = R"(usage: room_reverb mushra serve DIR [--port 8000] [--host 127.0.0.1] [--timeout 10]

serve: serves the test page of a test made by `mushra make` over HTTP, so that each
listener's results are also saved on this machine: the page posts its CSV to /results,
which is checked (the columns `mushra analyze` needs, scores on the test's scale, pages
of this test) and saved as DIR/results/<listener>_<YYYYmmdd-HHMMSS>.csv. Files outside
DIR are never served. Prints the address, then each saved file; Ctrl-C (SIGINT) or
SIGTERM stops it. The page works without the server too (open DIR/index.html): then the
results are only downloaded.

  --port N             TCP port (default 8000; 0 picks a free one and prints it)
  --host ADDRESS       address to listen on (default 127.0.0.1, this machine only;
                       0.0.0.0 lets other machines of the network connect)
  --timeout S          seconds a request may take to arrive whole (default 10; a
                       client that has not sent it by then is answered 408 and
                       dropped, so a stalled browser never holds the server)

)";

int runMushraServe(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"port", "host", "timeout"}, {});
  if (args.positional().empty()) throw UsageError("name the test folder: room_reverb mushra serve DIR");
  if (args.positional().size() > 1) throw UsageError("unexpected argument '" + args.positional()[1] + "'");
  const std::string dir = args.positional().front();
  HttpServerOptions options;
  options.port = args.intValue("port", 8000);
  options.host = args.value("host", "127.0.0.1");
  if (options.port < 0 || options.port > 65535) throw UsageError("--port must lie in 0..65535");
  options.timeout_s = args.intValue("timeout", 10);
  if (options.timeout_s < 1 || options.timeout_s > 3600) throw UsageError("--timeout must lie in 1..3600 s");

  MushraRequestHandler handler(dir);
  std::mutex output;  // whole lines from the connections' threads
  handler.on_saved = [&output](const std::string& path, const std::string& listener, std::size_t rows) {
    const std::lock_guard<std::mutex> lock(output);
    std::cout << "saved " << rows << " ratings of " << listener << " to " << path << std::endl;
  };
  HttpServer server(options, [&handler](const HttpRequest& request) { return handler(request); });
  installStopHandlers();
  const bool any_address = options.host == "0.0.0.0" || options.host == "::";
  const std::string shown_host = any_address ? "127.0.0.1" : (options.host.find(':') != std::string::npos
                                                                   ? "[" + options.host + "]" : options.host);
  // The test reads the port from this line; std::endl flushes it at once.
  std::cout << "serving " << dir << " at http://" << shown_host << ":" << server.port() << "/ (Ctrl-C stops)"
            << std::endl;
  server.serve(stop_requested);
  std::cout << "stopped" << std::endl;
  return 0;
}

}  // namespace room_reverb::tool
