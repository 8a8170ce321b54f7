#pragma once
// What `room_reverb mushra serve DIR` answers (the HTTP side is http_server.h):
//   GET/HEAD /path     the file DIR/path ("/" is index.html), with its content type; 403
//                      for a path with a ".." segment (nothing outside DIR is served)
//                      or one that leaves DIR through a link, 404 for no such file
//   POST /results      a results CSV as the test page saves it: checked as
//                      `mushra analyze` reads it (the required columns, scores on the
//                      test's scale) and against the test (pages it has), then saved as
//                      DIR/results/<listener>_<YYYYmmdd-HHMMSS>.csv; answers 201 and
//                      {"saved": "results/..."}, or 400 and {"error": "..."}
//   anything else      405
#include <functional>
#include <set>
#include <string>

#include "room_reverb/common/http_server.h"
#include "room_reverb/listening/mushra_results.h"

namespace room_reverb::core {

// The content type of a file by its extension (application/octet-stream when unknown).
std::string contentTypeOf(const std::string& path);

// A listener's name as a file name part: letters, digits, '_', '-', '.', at most 60
// characters, never empty or a dot name.
std::string safeFileNamePart(const std::string& text);

class MushraRequestHandler {
 public:
  // InputError unless `dir` holds a test: "<dir>: no test.json (make the test with
  // room_reverb mushra make)", or a test.json that is not a room_reverb test.
  explicit MushraRequestHandler(const std::string& dir);

  // Thread-safe (the server calls it from several connections at once).
  HttpResponse operator()(const HttpRequest& request);

  // Called with the saved file's path (and the listener) after each accepted POST, on
  // the connection's thread: several may call it at once.
  std::function<void(const std::string& path, const std::string& listener, std::size_t rows)> on_saved;

  MushraScale scale() const { return scale_; }

 private:
  HttpResponse serveFile(const HttpRequest& request) const;
  HttpResponse saveResults(const HttpRequest& request);

  std::string root_;  // canonical
  MushraScale scale_ = MushraScale::kZeroToFive;
  std::set<std::string> page_ids_;
};

}  // namespace room_reverb::core
