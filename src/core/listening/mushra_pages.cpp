#include "room_reverb/listening/mushra_pages.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace room_reverb::core {
namespace {

// FNV-1a: a fixed, portable hash of the page id (std::hash may differ between libraries).
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

// A uniform draw in [0, bound) from 32-bit words, by rejection: std::uniform_int_distribution
// is implementation-defined, and a plain modulo would favour the small values.
std::uint32_t uniformBelow(std::mt19937& engine, std::uint32_t bound) {
  const std::uint32_t limit = static_cast<std::uint32_t>((0x100000000ull / bound) * bound - 1);
  std::uint32_t draw = 0;
  do {
    draw = static_cast<std::uint32_t>(engine());
  } while (draw > limit);
  return draw % bound;
}

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

}  // namespace

std::vector<std::size_t> shuffledPositions(std::size_t count, std::uint32_t seed, const std::string& page_id) {
  const std::uint64_t hash = fnv1a(page_id);
  std::seed_seq sequence{seed, static_cast<std::uint32_t>(hash), static_cast<std::uint32_t>(hash >> 32)};
  std::mt19937 engine(sequence);
  std::vector<std::size_t> positions(count);
  std::iota(positions.begin(), positions.end(), 0);
  for (std::size_t i = count; i > 1; --i) {
    std::swap(positions[i - 1], positions[uniformBelow(engine, static_cast<std::uint32_t>(i))]);
  }
  return positions;
}

std::vector<MushraPage> mushraPages(const MushraPlan& plan) {
  std::vector<MushraPage> pages;
  for (const MushraRoom& room : plan.rooms) {
    for (const MushraContent& content : plan.contents) {
      for (const MushraAttribute& attribute : plan.attributes) {
        MushraPage page;
        page.id = room.name + "/" + content.name + "/" + attribute.id;
        page.room = room.name;
        page.content = content.name;
        page.attribute = attribute.id;
        page.question = attribute.question;
        page.show_panorama = attribute.show_panorama;
        // Condition i gets letter number positions[i].
        const std::vector<std::size_t> positions = shuffledPositions(plan.conditions.size(), plan.seed, page.id);
        page.stimuli.resize(plan.conditions.size());
        for (std::size_t i = 0; i < plan.conditions.size(); ++i) {
          MushraPageStimulus& s = page.stimuli[positions[i]];
          s.condition = plan.conditions[i];
          s.letter = std::string(1, static_cast<char>('A' + positions[i]));
          s.is_hidden_anchor = contains(plan.hidden_anchors, s.condition);
          s.is_shown_reference = contains(plan.shown_references, s.condition);
        }
        pages.push_back(std::move(page));
      }
    }
  }
  return pages;
}

}  // namespace room_reverb::core
