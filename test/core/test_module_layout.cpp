// The product's layout and wording, checked on the sources themselves:
// - a module's dependencies point one way: the visual route (vision/) does not include the
//   synthetic-capture generator (synthetic_capture/), which renders rooms for it to see, and
//   the comparison (evaluation/) does not include the diagnosis (diagnosis/) built on it;
// - the product says what the system is and does now: no comment, test, document, script or
//   configuration narrates the team's numbered rounds of development (that is git log's job).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot(ROOM_REVERB_SOURCE_DIR);

// Lines of every regular file under `root` (a file or a folder) matching `pattern`, as
// "path:line: text".
std::vector<std::string> linesMatching(const fs::path& root, const std::regex& pattern) {
  std::vector<fs::path> files;
  if (fs::is_regular_file(root)) {
    files.push_back(root);
  } else if (fs::is_directory(root)) {
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  }
  std::vector<std::string> hits;
  for (const fs::path& file : files) {
    const std::string ext = file.extension().string();
    // Binary and generated data carry no prose.
    if (ext == ".png" || ext == ".wav" || ext == ".gz" || ext == ".tif" || ext == ".bag" || ext == ".sofa") continue;
    std::ifstream in(file);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (std::regex_search(line, pattern)) {
        hits.push_back(fs::relative(file, kRoot).string() + ":" + std::to_string(number) + ": " + line);
      }
    }
  }
  return hits;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

std::regex includeOf(const std::string& module) {
  return std::regex(R"(^\s*#\s*include\s*[<"]room_reverb/)" + module + "/");
}

// A numbered round of development (the word for a working period or a round, then its
// number; the test below spells the cases out). Written so that
// this file does not match itself.
const std::regex kHistory(std::string("\\b(sess") + "ions?|rou" + "nds?)\\s+[0-9]+", std::regex::icase);

}  // namespace

TEST(ModuleLayout, VisionDoesNotIncludeTheCaptureGenerator) {
  std::vector<std::string> hits = linesMatching(kRoot / "src" / "core" / "vision", includeOf("synthetic_capture"));
  const std::vector<std::string> headers =
      linesMatching(kRoot / "include" / "room_reverb" / "vision", includeOf("synthetic_capture"));
  hits.insert(hits.end(), headers.begin(), headers.end());
  EXPECT_TRUE(hits.empty()) << joined(hits);
  // The generator does build on the route's projections: the check looks at real includes.
  EXPECT_FALSE(linesMatching(kRoot / "src" / "core" / "synthetic_capture", includeOf("vision")).empty());
}

TEST(ModuleLayout, ComparisonDoesNotIncludeTheDiagnosis) {
  std::vector<std::string> hits = linesMatching(kRoot / "src" / "core" / "evaluation", includeOf("diagnosis"));
  const std::vector<std::string> headers =
      linesMatching(kRoot / "include" / "room_reverb" / "evaluation", includeOf("diagnosis"));
  hits.insert(hits.end(), headers.begin(), headers.end());
  EXPECT_TRUE(hits.empty()) << joined(hits);
  EXPECT_FALSE(linesMatching(kRoot / "include" / "room_reverb" / "diagnosis", includeOf("evaluation")).empty());
}

TEST(ModuleLayout, IncludePatternMatchesOnlyIncludes) {
  const std::regex pattern = includeOf("diagnosis");
  EXPECT_TRUE(std::regex_search("#include \"room_reverb/diagnosis/diagnosis.h\"", pattern));
  EXPECT_TRUE(std::regex_search("  #  include <room_reverb/diagnosis/x.h>", pattern));
  EXPECT_FALSE(std::regex_search("// see room_reverb/diagnosis/diagnosis.h", pattern));
  EXPECT_FALSE(std::regex_search("#include \"room_reverb/evaluation/measurements.h\"", pattern));
}

TEST(ProductWording, NoDevelopmentHistory) {
  std::vector<std::string> hits;
  for (const char* part : {"src", "include", "test", "bench", "docs", "config", "launch", "scripts", "msg", "srv",
                           "web", "README.md", "CMakeLists.txt", "package.xml"}) {
    const std::vector<std::string> found = linesMatching(kRoot / part, kHistory);
    hits.insert(hits.end(), found.begin(), found.end());
  }
  EXPECT_TRUE(hits.empty()) << "development history belongs in git log, not in the product:\n" << joined(hits);
}

TEST(ProductWording, HistoryPatternCatchesNumberedRounds) {
  const std::string s = "Ses" "sion";
  EXPECT_TRUE(std::regex_search("(docs/diagnosis.md, " + s + " 16)", kHistory));
  EXPECT_TRUE(std::regex_search("until " + s + " 14 two", kHistory));
  EXPECT_TRUE(std::regex_search(s + "s 8-19 built it", kHistory));
  EXPECT_TRUE(std::regex_search("after ro" "und 3 of tuning", kHistory));
  EXPECT_FALSE(std::regex_search("a listening-test " + s + " of 20 minutes", kHistory));
  EXPECT_FALSE(std::regex_search("rounds the level to 0.1 dB", kHistory));
}
