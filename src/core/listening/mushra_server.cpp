#include "room_reverb/listening/mushra_server.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

HttpResponse jsonResponse(int status, const json& body) { return {status, "application/json", body.dump() + "\n"}; }

std::string localTimestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm local{};
  localtime_r(&now, &local);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%d-%H%M%S", &local);
  return text;
}

// Whether `path` lies inside `root` (both canonical or weakly canonical).
bool isInside(const fs::path& path, const fs::path& root) {
  return std::mismatch(root.begin(), root.end(), path.begin(), path.end()).first == root.end();
}

}  // namespace

std::string contentTypeOf(const std::string& path) {
  static const std::map<std::string, std::string> types = {
      {".html", "text/html; charset=utf-8"},  {".js", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},    {".json", "application/json"},
      {".wav", "audio/wav"},                  {".flac", "audio/flac"},
      {".png", "image/png"},                  {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},                {".webp", "image/webp"},
      {".svg", "image/svg+xml"},              {".csv", "text/csv; charset=utf-8"},
      {".yaml", "text/yaml; charset=utf-8"},  {".txt", "text/plain; charset=utf-8"},
      {".md", "text/markdown; charset=utf-8"}, {".ico", "image/x-icon"}};
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto found = types.find(extension);
  return found == types.end() ? "application/octet-stream" : found->second;
}

std::string safeFileNamePart(const std::string& text) {
  std::string safe;
  for (unsigned char c : text) {
    const bool keep = std::isalnum(c) || c == '_' || c == '-' || c == '.';
    if (keep) safe += static_cast<char>(c);
    else if (safe.empty() || safe.back() != '_') safe += '_';
    if (safe.size() >= 60) break;
  }
  if (safe.find_first_not_of("._") == std::string::npos) return "listener";
  return safe;
}

MushraRequestHandler::MushraRequestHandler(const std::string& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) throw InputError(dir + ": no such folder (expected a MUSHRA test folder)");
  const fs::path test_file = fs::path(dir) / "test.json";
  if (!fs::is_regular_file(test_file, error)) {
    throw InputError(dir + ": no test.json (make the test with room_reverb mushra make)");
  }
  json test;
  try {
    test = json::parse(readTextFile(test_file.string(), "MUSHRA test"));
    scale_ = parseMushraScale(test.at("scale").at("name").get<std::string>());
    for (const json& page : test.at("pages")) page_ids_.insert(page.at("id").get<std::string>());
  } catch (const json::exception& e) {
    throw InputError(test_file.string() + ": not a room_reverb MUSHRA test (" + e.what() + ")");
  }
  root_ = fs::canonical(dir).string();
}

HttpResponse MushraRequestHandler::operator()(const HttpRequest& request) {
  if (request.path == "/results") {
    if (request.method != "POST") return httpTextResponse(405, "POST the results CSV to /results");
    return saveResults(request);
  }
  if (request.method != "GET" && request.method != "HEAD") {
    return httpTextResponse(405, request.method + " is not allowed here (GET files, POST /results)");
  }
  return serveFile(request);
}

HttpResponse MushraRequestHandler::serveFile(const HttpRequest& request) const {
  std::string relative = request.path.substr(1);
  if (relative.empty() || relative.back() == '/') relative += "index.html";
  // Refused by its segments before the file system is asked: "..", and the separators
  // another system would take (a backslash) never name a file of a test.
  std::stringstream segments(relative);
  std::string segment;
  while (std::getline(segments, segment, '/')) {
    if (segment == ".." || segment.find('\\') != std::string::npos) {
      return httpTextResponse(403, "paths outside the test folder are not served");
    }
  }
  const fs::path root(root_);
  std::error_code error;
  const fs::path file = fs::weakly_canonical(root / relative, error);
  if (error || !isInside(file, root)) return httpTextResponse(403, "paths outside the test folder are not served");
  if (!fs::is_regular_file(file, error)) return httpTextResponse(404, request.path + ": no such file in the test");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream body;
  body << in.rdbuf();
  if (!in) return httpTextResponse(500, request.path + ": cannot read the file");
  return {200, contentTypeOf(file.string()), body.str()};
}

HttpResponse MushraRequestHandler::saveResults(const HttpRequest& request) {
  std::vector<MushraRating> ratings;
  try {
    ratings = parseMushraResultsCsv(request.body, "the posted results", scale_);
  } catch (const InputError& e) {
    return jsonResponse(400, {{"error", e.what()}});
  }
  for (const MushraRating& r : ratings) {
    if (!page_ids_.count(r.page)) {
      return jsonResponse(400, {{"error", r.origin + ": page '" + r.page + "' is not a page of this test"}});
    }
  }
  const std::string listener = ratings.front().listener;
  const fs::path folder = fs::path(root_) / "results";
  // Listeners finishing in the same second race for one name; each write claims its name
  // or tries the next, so no lock is held while a file goes to the disk.
  const std::string stem = safeFileNamePart(listener) + "_" + localTimestamp();
  fs::path file = folder / (stem + ".csv");
  try {
    createFolder(folder.string());
    for (int n = 2; !writeNewFileAtomically(file.string(), request.body); ++n) {
      file = folder / (stem + "-" + std::to_string(n) + ".csv");
    }
  } catch (const InputError& e) {
    return jsonResponse(500, {{"error", e.what()}});
  }
  if (on_saved) on_saved(file.string(), listener, ratings.size());
  return jsonResponse(201, {{"saved", "results/" + file.filename().string()}});
}

}  // namespace room_reverb::core
