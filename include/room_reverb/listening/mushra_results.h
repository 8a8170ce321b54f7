#pragma once
// Results of MUSHRA listening tests (ITU-R BS.1534-3, and the audio-visual variant of
// Remaggi et al. with a 0-5 scale): reading the CSV files the test page saves, merging
// several of them, and refusing what would give a wrong statistic. Every problem a user
// can cause is an InputError naming the file and line; a listener who did not finish the
// test is not an error but a stated exclusion.
#include <string>
#include <vector>

namespace room_reverb::core {

// The rating scale of a test.
enum class MushraScale {
  kZeroToFive,     // integers 0..5, as in Remaggi et al.'s tests
  kZeroToHundred,  // the 0..100 continuous quality scale of ITU-R BS.1534-3
};
// "0-5" or "0-100"; InputError otherwise.
MushraScale parseMushraScale(const std::string& text);
std::string toString(MushraScale scale);

// One row of a results file: one listener's score for one stimulus of one page.
struct MushraRating {
  std::string listener;
  std::string page;  // the page as the listener's results name it
  std::string room;
  std::string content;
  std::string attribute;
  std::string condition;
  std::string letter;
  double score = 0.0;
  double duration_s = 0.0;
  std::string origin;  // "file:line", so that messages can point at the row
};

// What a page asks, the same for every listener (page ids may be listener-specific
// positions in a randomised order): a room, a dry content and an attribute.
struct MushraTrial {
  std::string room;
  std::string content;
  std::string attribute;
  bool operator<(const MushraTrial& other) const;
  bool operator==(const MushraTrial& other) const;
};
MushraTrial trialOf(const MushraRating& rating);
std::string toString(const MushraTrial& trial);  // "room / content / attribute"

struct ListenerExclusion {
  std::string listener;
  std::string reason;
};

struct MushraResults {
  std::vector<MushraRating> ratings;          // of the listeners who completed the test, in file order
  std::vector<std::string> listeners;         // every listener seen, in order of appearance
  std::vector<ListenerExclusion> incomplete;  // listeners left out for missing pages or ratings
};

// The columns a results file must have (in any order; others are ignored).
const std::vector<std::string>& mushraResultColumns();

// The ratings of one results file's text (RFC 4180 CSV: quoted fields, doubled quotes,
// CRLF or LF). `source` names the file in messages. InputError for an empty file, a
// header without ratings, missing columns (named), a row with the wrong number of
// fields, a score that is not a number or lies outside `scale` (0-5 also requires
// integers), or a duration that is not a non-negative number.
std::vector<MushraRating> parseMushraResultsCsv(const std::string& text, const std::string& source, MushraScale scale);

// Merges the ratings of one or more files. InputError for a listener who rated the same
// condition twice on a page (both rows named), or whose page names two rooms, contents
// or attributes, or who met the same room/content/attribute on two pages (pairing by
// page would be ambiguous). A listener who lacks a page or a rating that other listeners
// have is left out with the
// reason, not counted silently: the expected pages are every room/content/attribute
// any listener rated, and on each the conditions any listener rated there.
MushraResults combineMushraRatings(const std::vector<MushraRating>& ratings);

// parseMushraResultsCsv on every file, then combineMushraRatings. InputError when no
// file is given or a file cannot be read.
MushraResults readMushraResults(const std::vector<std::string>& paths, MushraScale scale);

}  // namespace room_reverb::core
