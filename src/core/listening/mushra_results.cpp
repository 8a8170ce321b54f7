#include "room_reverb/listening/mushra_results.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <map>
#include <set>
#include <tuple>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

struct CsvRecord {
  std::vector<std::string> fields;
  int line = 0;  // where the record starts (a quoted field may span lines)
};

// RFC 4180 records, written here because the format is small and no CSV library is among
// the project's dependencies. Lenient where spreadsheets are: LF or CRLF, a UTF-8 byte
// order mark, blank lines skipped.
std::vector<CsvRecord> splitCsv(const std::string& text, const std::string& source) {
  std::vector<CsvRecord> records;
  std::size_t i = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  int line = 1;
  CsvRecord record{{}, line};
  std::string field;
  bool quoted_field = false;  // the current field was quoted: keep its spaces
  auto endField = [&] {
    record.fields.push_back(field);
    field.clear();
    quoted_field = false;
  };
  auto endRecord = [&] {
    endField();
    const bool blank = record.fields.size() == 1 && record.fields[0].find_first_not_of(" \t") == std::string::npos;
    if (!blank) records.push_back(record);
    record = CsvRecord{{}, line};
  };
  while (i < text.size()) {
    const char c = text[i];
    if (c == '"' && field.find_first_not_of(" \t") == std::string::npos && !quoted_field) {
      const int opened_at = line;
      field.clear();
      ++i;
      while (true) {
        if (i >= text.size())
          throw InputError(source + ":" + std::to_string(opened_at) + ": unterminated quoted field");
        if (text[i] == '"') {
          if (i + 1 < text.size() && text[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        if (text[i] == '\n') ++line;
        field += text[i++];
      }
      quoted_field = true;
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      if (i < text.size() && text[i] != ',' && text[i] != '\n' && text[i] != '\r') {
        throw InputError(source + ":" + std::to_string(line) + ": text after a closing quote");
      }
      continue;
    }
    if (c == ',') {
      endField();
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      ++line;
      endRecord();
    } else {
      field += c;
    }
    ++i;
  }
  if (!field.empty() || !record.fields.empty() || quoted_field) endRecord();
  return records;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// A finite number that fills the whole field ("nan" and "inf" parse with strtod but are
// no score).
bool parseNumber(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return *end == '\0' && std::isfinite(value);
}

double checkedScore(const std::string& text, MushraScale scale, const std::string& where) {
  double score = 0.0;
  if (!parseNumber(text, score)) throw InputError(where + ": score '" + text + "' is not a number");
  const double maximum = scale == MushraScale::kZeroToFive ? 5.0 : 100.0;
  if (score < 0.0 || score > maximum) {
    throw InputError(where + ": score " + text + " is outside the " + toString(scale) +
                     " scale (use --scale to name the test's scale)");
  }
  if (scale == MushraScale::kZeroToFive && score != std::floor(score)) {
    throw InputError(where + ": score " + text + " is not an integer, as the 0-5 scale requires");
  }
  return score;
}

std::string listOf(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "'" : ", '") + name + "'";
  return text;
}

// "a, b, c and 4 more": a reason stays one readable line however much is missing.
std::string shortList(const std::vector<std::string>& items) {
  constexpr std::size_t kShown = 3;
  std::string text;
  for (std::size_t i = 0; i < std::min(items.size(), kShown); ++i) text += (i == 0 ? "" : ", ") + items[i];
  if (items.size() > kShown) text += " and " + std::to_string(items.size() - kShown) + " more";
  return text;
}

// Rows of one listener that must agree: a page asks one trial, a trial is met on one page.
void checkPageIdentity(const std::vector<MushraRating>& ratings) {
  std::map<std::pair<std::string, std::string>, const MushraRating*> page_first;
  std::map<std::pair<std::string, MushraTrial>, const MushraRating*> trial_first;
  for (const MushraRating& rating : ratings) {
    const auto page = page_first.emplace(std::make_pair(rating.listener, rating.page), &rating).first->second;
    if (!(trialOf(*page) == trialOf(rating))) {
      throw InputError(rating.origin + ": listener '" + rating.listener + "' page '" + rating.page + "' asks '" +
                       toString(trialOf(rating)) + "' here but '" + toString(trialOf(*page)) + "' at " + page->origin);
    }
    const auto trial = trial_first.emplace(std::make_pair(rating.listener, trialOf(rating)), &rating).first->second;
    if (trial->page != rating.page) {
      throw InputError(rating.origin + ": listener '" + rating.listener + "' met '" + toString(trialOf(rating)) +
                       "' on two pages ('" + trial->page + "' at " + trial->origin + " and '" + rating.page +
                       "'); paired tests need one page per room, content and attribute");
    }
  }
}

void checkDuplicates(const std::vector<MushraRating>& ratings) {
  std::map<std::tuple<std::string, std::string, std::string>, const MushraRating*> seen;
  for (const MushraRating& rating : ratings) {
    const auto [first, inserted] =
        seen.emplace(std::make_tuple(rating.listener, rating.page, rating.condition), &rating);
    if (!inserted) {
      throw InputError("listener '" + rating.listener + "' rated condition '" + rating.condition + "' twice on page '" +
                       rating.page + "' (" + first->second->origin + " and " + rating.origin + ")");
    }
  }
}

// What each listener lacks of the union of every listener's trials and of the
// conditions rated on each trial; empty for a complete listener.
std::map<std::string, std::string> incompleteness(const std::vector<MushraRating>& ratings,
                                                  const std::vector<std::string>& listeners) {
  std::map<MushraTrial, std::set<std::string>> expected;
  std::map<std::string, std::map<MushraTrial, std::set<std::string>>> rated;
  for (const MushraRating& rating : ratings) {
    expected[trialOf(rating)].insert(rating.condition);
    rated[rating.listener][trialOf(rating)].insert(rating.condition);
  }
  std::map<std::string, std::string> reasons;
  for (const std::string& listener : listeners) {
    const auto& own = rated[listener];
    std::vector<std::string> missing_pages, missing_ratings;
    for (const auto& [trial, conditions] : expected) {
      const auto found = own.find(trial);
      if (found == own.end()) {
        missing_pages.push_back(toString(trial));
        continue;
      }
      for (const std::string& condition : conditions) {
        if (!found->second.count(condition)) missing_ratings.push_back(condition + " on " + toString(trial));
      }
    }
    std::string reason;
    if (!missing_pages.empty()) {
      reason = "incomplete: rated " + std::to_string(own.size()) + " of " + std::to_string(expected.size()) +
               " pages (missing " + shortList(missing_pages) + ")";
    }
    if (!missing_ratings.empty()) {
      reason += (reason.empty() ? "incomplete: " : "; ") + std::string("no rating for ") + shortList(missing_ratings);
    }
    if (!reason.empty()) reasons[listener] = reason;
  }
  return reasons;
}

}  // namespace

MushraScale parseMushraScale(const std::string& text) {
  if (text == "0-5") return MushraScale::kZeroToFive;
  if (text == "0-100") return MushraScale::kZeroToHundred;
  throw InputError("unknown rating scale '" + text + "' (expected 0-5 or 0-100)");
}

std::string toString(MushraScale scale) { return scale == MushraScale::kZeroToFive ? "0-5" : "0-100"; }

bool MushraTrial::operator<(const MushraTrial& other) const {
  return std::tie(room, content, attribute) < std::tie(other.room, other.content, other.attribute);
}

bool MushraTrial::operator==(const MushraTrial& other) const {
  return std::tie(room, content, attribute) == std::tie(other.room, other.content, other.attribute);
}

MushraTrial trialOf(const MushraRating& rating) { return {rating.room, rating.content, rating.attribute}; }

std::string toString(const MushraTrial& trial) { return trial.room + " / " + trial.content + " / " + trial.attribute; }

const std::vector<std::string>& mushraResultColumns() {
  static const std::vector<std::string> columns = {"listener",  "page",   "room",  "content",   "attribute",
                                                   "condition", "letter", "score", "duration_s"};
  return columns;
}

std::vector<MushraRating> parseMushraResultsCsv(const std::string& text, const std::string& source, MushraScale scale) {
  const std::vector<CsvRecord> records = splitCsv(text, source);
  if (records.empty()) {
    throw InputError(source + ": empty results file (expected the header " + listOf(mushraResultColumns()) +
                     " and one row per rating)");
  }
  const CsvRecord& header = records.front();
  std::map<std::string, std::size_t> column_index;
  for (std::size_t i = 0; i < header.fields.size(); ++i) column_index.emplace(lowercase(trimmed(header.fields[i])), i);
  std::vector<std::string> missing;
  std::vector<std::size_t> index;  // of each required column, in mushraResultColumns() order
  for (const std::string& column : mushraResultColumns()) {
    const auto found = column_index.find(column);
    if (found == column_index.end())
      missing.push_back(column);
    else
      index.push_back(found->second);
  }
  if (!missing.empty()) {
    throw InputError(source + ": missing column" + (missing.size() > 1 ? "s " : " ") + listOf(missing) +
                     " in the header line");
  }
  if (records.size() == 1) throw InputError(source + ": has a header but no ratings");

  std::vector<MushraRating> ratings;
  for (std::size_t r = 1; r < records.size(); ++r) {
    const CsvRecord& record = records[r];
    const std::string where = source + ":" + std::to_string(record.line);
    if (record.fields.size() != header.fields.size()) {
      throw InputError(where + ": " + std::to_string(record.fields.size()) + " fields where the header has " +
                       std::to_string(header.fields.size()));
    }
    auto field = [&](std::size_t k) { return trimmed(record.fields[index[k]]); };
    MushraRating rating{field(0), field(1), field(2), field(3), field(4), field(5), field(6), 0.0, 0.0, where};
    for (std::size_t k = 0; k < 6; ++k) {
      if (field(k).empty()) throw InputError(where + ": empty " + mushraResultColumns()[k]);
    }
    rating.score = checkedScore(field(7), scale, where);
    if (!parseNumber(field(8), rating.duration_s) || rating.duration_s < 0.0) {
      throw InputError(where + ": duration_s '" + field(8) + "' is not a non-negative number of seconds");
    }
    ratings.push_back(std::move(rating));
  }
  return ratings;
}

MushraResults combineMushraRatings(const std::vector<MushraRating>& ratings) {
  checkDuplicates(ratings);
  checkPageIdentity(ratings);
  MushraResults results;
  for (const MushraRating& rating : ratings) {
    if (std::find(results.listeners.begin(), results.listeners.end(), rating.listener) == results.listeners.end()) {
      results.listeners.push_back(rating.listener);
    }
  }
  const auto reasons = incompleteness(ratings, results.listeners);
  for (const std::string& listener : results.listeners) {
    const auto found = reasons.find(listener);
    if (found != reasons.end()) results.incomplete.push_back({listener, found->second});
  }
  std::copy_if(ratings.begin(), ratings.end(), std::back_inserter(results.ratings),
               [&](const MushraRating& rating) { return !reasons.count(rating.listener); });
  return results;
}

MushraResults readMushraResults(const std::vector<std::string>& paths, MushraScale scale) {
  if (paths.empty()) throw InputError("no results file given (expected one or more CSV files of MUSHRA ratings)");
  std::vector<MushraRating> all;
  for (const std::string& path : paths) {
    const auto ratings = parseMushraResultsCsv(readTextFile(path, "MUSHRA results CSV file"), path, scale);
    all.insert(all.end(), ratings.begin(), ratings.end());
  }
  return combineMushraRatings(all);
}

}  // namespace room_reverb::core
