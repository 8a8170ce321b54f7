#pragma once
// Post-screening of MUSHRA listeners: who is left out of the statistics, and why.
//
// Two rules, applied together when both are enabled:
// - Remaggi et al. (audio-visual MUSHRA with a 0-5 scale, section 4): a listener who
//   misidentifies the anchors more than twice is excluded. The paper does not define
//   "misidentifies"; checkPageAnchors below does, per page.
// - ITU-R BS.1534-3 section 4.1.2 (0-100 scale): an assessor who rates the hidden
//   reference below 90 for more than 15 % of the test items is excluded.
#include <cstddef>
#include <string>
#include <vector>

#include "room_reverb/listening/mushra_results.h"

namespace room_reverb::core {

struct ScreeningOptions {
  std::string reference = "reference";                    // the hidden reference (high anchor)
  std::vector<std::string> low_anchors = {"wrong_room"};  // hidden low anchors; may be empty
  bool anchor_rule = true;                                // Remaggi et al.
  int max_misidentifications = 2;                         // excluded with more than this many
  bool reference_score_rule = false;                      // ITU-R BS.1534-3 section 4.1.2
  double reference_threshold = 90.0;                      // a hidden reference rated below this is a miss...
  double max_fraction_below = 0.15;                       // ...and more than this fraction of pages excludes
};

// The paper's rule on the 0-5 scale; on 0-100 the BS.1534-3 rule as well (the anchor
// rule does not depend on the scale, and a BS.1534 test has hidden anchors too).
ScreeningOptions defaultScreeningOptions(MushraScale scale);

// One listener's page, judged by the anchor rule. Definitions (ours; the paper gives none):
// - the hidden reference is misidentified when its score is below the highest score of
//   the page's other stimuli: it must be rated highest or equal to the highest;
// - a low anchor is misidentified when its score is above the lowest score of the page's
//   stimuli that are not low anchors: it must be rated lowest or equal to that lowest.
//   Low anchors are not compared with each other: whether a wrong room sounds worse than
//   a 3.5 kHz low-pass is taste, not a failure to spot an anchor.
// Each misidentified anchor counts one, so a page counts at most 1 + its low anchors.
struct PageAnchorCheck {
  bool has_reference = false;
  bool reference_misidentified = false;
  int low_anchors_rated = 0;
  int low_anchors_misidentified = 0;
  int misidentifications() const { return (reference_misidentified ? 1 : 0) + low_anchors_misidentified; }
};
// `page`: every rating of one listener on one page.
PageAnchorCheck checkPageAnchors(const std::vector<MushraRating>& page, const ScreeningOptions& options);

struct ListenerScreening {
  std::string listener;
  std::size_t pages = 0;
  int misidentifications = 0;                 // anchor rule, summed over the pages
  std::size_t reference_pages = 0;            // pages with a rating of the hidden reference
  std::size_t reference_below_threshold = 0;  // of those, rated below reference_threshold
  bool kept = true;
  std::string reason;  // why the listener is excluded; empty when kept
};

struct ScreeningResult {
  std::vector<ListenerScreening> listeners;  // in order of appearance
  std::vector<std::string> kept() const;
  std::vector<ListenerExclusion> excluded() const;
};

// Screens every listener of `ratings`. InputError when an enabled rule needs a condition
// (the reference, a low anchor) that no rating has: the rule could not be applied, and
// passing everyone silently would hide that the names are wrong. A listener who never
// rated the reference cannot be screened and is excluded with that reason.
ScreeningResult screenListeners(const std::vector<MushraRating>& ratings, const ScreeningOptions& options);

// The ratings of the named listeners only, in their order in `ratings`.
std::vector<MushraRating> ratingsOfListeners(const std::vector<MushraRating>& ratings,
                                             const std::vector<std::string>& listeners);

}  // namespace room_reverb::core
