#pragma once
// The pages of a MUSHRA test and the letters of their stimuli. A page is one room, one dry
// content and one attribute; on it every condition of the plan is one stimulus behind a
// letter (A, B, C...). The letters are shuffled per page, so that a listener cannot learn
// which letter is the reference, and the shuffle is fixed by the plan's seed and the page,
// so that the same plan gives the same test (the page may shuffle the order of pages and
// letters once more per listener; the results name conditions, not letters).
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/listening/mushra_plan.h"

namespace room_reverb::core {

struct MushraPageStimulus {
  std::string condition;
  std::string letter;              // "A", "B", ...
  bool is_hidden_anchor = false;   // the plan's hidden_anchors
  bool is_shown_reference = false; // also offered as a labelled reference on the page
};

struct MushraPage {
  std::string id;  // room/content/attribute, unique in the test
  std::string room;
  std::string content;
  std::string attribute;
  std::string question;
  bool show_panorama = false;
  std::vector<MushraPageStimulus> stimuli;  // in letter order
};

// Every page: rooms in plan order, then contents, then attributes.
std::vector<MushraPage> mushraPages(const MushraPlan& plan);

// The positions 0..count-1 in a random order that depends only on `seed` and `page_id`
// (not on the page's place in the test, so adding a room leaves the other pages' letters
// alone). Fisher-Yates over std::mt19937 with draws by rejection, both of which the C++
// standard fixes exactly, so every platform gives the same order.
std::vector<std::size_t> shuffledPositions(std::size_t count, std::uint32_t seed, const std::string& page_id);

}  // namespace room_reverb::core
