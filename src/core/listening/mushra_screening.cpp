#include "room_reverb/listening/mushra_screening.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

bool isLowAnchor(const std::string& condition, const ScreeningOptions& options) {
  return std::find(options.low_anchors.begin(), options.low_anchors.end(), condition) != options.low_anchors.end();
}

// A rule that names a condition no rating has would pass everyone; say so instead.
void requireCondition(const std::vector<MushraRating>& ratings, const std::string& condition, const std::string& role,
                      const std::string& option) {
  const bool found = std::any_of(ratings.begin(), ratings.end(),
                                 [&](const MushraRating& rating) { return rating.condition == condition; });
  if (!found) {
    throw InputError("no rating of condition '" + condition + "', the " + role + " the screening needs; name it with " +
                     option);
  }
}

std::string percent(double fraction) {
  std::ostringstream text;
  text.precision(3);
  text << 100.0 * fraction << " %";
  return text.str();
}

// Why the rules exclude this listener; empty when they keep them.
std::string exclusionReason(const ListenerScreening& listener, const ScreeningOptions& options) {
  if (listener.reference_pages == 0) {
    return "never rated the hidden reference '" + options.reference + "', so cannot be screened";
  }
  std::vector<std::string> reasons;
  if (options.anchor_rule && listener.misidentifications > options.max_misidentifications) {
    reasons.push_back("misidentified the anchors " + std::to_string(listener.misidentifications) +
                      " times (more than " + std::to_string(options.max_misidentifications) + ")");
  }
  const double fraction_below =
      static_cast<double>(listener.reference_below_threshold) / static_cast<double>(listener.reference_pages);
  if (options.reference_score_rule && fraction_below > options.max_fraction_below) {
    std::ostringstream threshold;
    threshold << options.reference_threshold;
    reasons.push_back("rated the hidden reference below " + threshold.str() + " on " +
                      std::to_string(listener.reference_below_threshold) + " of " +
                      std::to_string(listener.reference_pages) + " pages (" + percent(fraction_below) + ", more than " +
                      percent(options.max_fraction_below) + ", ITU-R BS.1534-3 4.1.2)");
  }
  std::string reason;
  for (const auto& part : reasons) reason += (reason.empty() ? "" : "; ") + part;
  return reason;
}

}  // namespace

ScreeningOptions defaultScreeningOptions(MushraScale scale) {
  ScreeningOptions options;
  options.reference_score_rule = scale == MushraScale::kZeroToHundred;
  return options;
}

PageAnchorCheck checkPageAnchors(const std::vector<MushraRating>& page, const ScreeningOptions& options) {
  PageAnchorCheck check;
  double reference_score = 0.0;
  double highest_other = -std::numeric_limits<double>::infinity();
  double lowest_not_low_anchor = std::numeric_limits<double>::infinity();
  for (const MushraRating& rating : page) {
    if (rating.condition == options.reference) {
      check.has_reference = true;
      reference_score = rating.score;
    } else {
      highest_other = std::max(highest_other, rating.score);
    }
    if (!isLowAnchor(rating.condition, options)) lowest_not_low_anchor = std::min(lowest_not_low_anchor, rating.score);
  }
  check.reference_misidentified = check.has_reference && reference_score < highest_other;
  for (const MushraRating& rating : page) {
    if (!isLowAnchor(rating.condition, options)) continue;
    ++check.low_anchors_rated;
    if (rating.score > lowest_not_low_anchor) ++check.low_anchors_misidentified;
  }
  return check;
}

std::vector<std::string> ScreeningResult::kept() const {
  std::vector<std::string> names;
  for (const auto& listener : listeners) {
    if (listener.kept) names.push_back(listener.listener);
  }
  return names;
}

std::vector<ListenerExclusion> ScreeningResult::excluded() const {
  std::vector<ListenerExclusion> exclusions;
  for (const auto& listener : listeners) {
    if (!listener.kept) exclusions.push_back({listener.listener, listener.reason});
  }
  return exclusions;
}

ScreeningResult screenListeners(const std::vector<MushraRating>& ratings, const ScreeningOptions& options) {
  if (options.anchor_rule || options.reference_score_rule) {
    requireCondition(ratings, options.reference, "hidden reference", "--reference");
  }
  if (options.anchor_rule) {
    for (const auto& anchor : options.low_anchors) requireCondition(ratings, anchor, "low anchor", "--low-anchors");
  }
  // Pages of each listener, both in order of appearance.
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, std::vector<MushraRating>>> pages;
  for (const MushraRating& rating : ratings) {
    if (!pages.count(rating.listener)) order.push_back(rating.listener);
    pages[rating.listener][rating.page].push_back(rating);
  }
  ScreeningResult result;
  for (const std::string& name : order) {
    ListenerScreening listener;
    listener.listener = name;
    for (const auto& [page_name, page] : pages[name]) {
      ++listener.pages;
      listener.misidentifications += checkPageAnchors(page, options).misidentifications();
      for (const MushraRating& rating : page) {
        if (rating.condition != options.reference) continue;
        ++listener.reference_pages;
        if (rating.score < options.reference_threshold) ++listener.reference_below_threshold;
      }
    }
    if (options.anchor_rule || options.reference_score_rule) listener.reason = exclusionReason(listener, options);
    listener.kept = listener.reason.empty();
    result.listeners.push_back(listener);
  }
  return result;
}

std::vector<MushraRating> ratingsOfListeners(const std::vector<MushraRating>& ratings,
                                             const std::vector<std::string>& listeners) {
  std::vector<MushraRating> kept;
  std::copy_if(ratings.begin(), ratings.end(), std::back_inserter(kept), [&](const MushraRating& rating) {
    return std::find(listeners.begin(), listeners.end(), rating.listener) != listeners.end();
  });
  return kept;
}

}  // namespace room_reverb::core
