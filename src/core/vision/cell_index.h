#pragma once
// Integer 3D cells -> indices, in one flat open-addressed table (linear probing,
// Fibonacci hashing of the packed cell).
//
// Why not std::unordered_map: it keeps a node per entry, so every lookup is a pointer
// chase to a cache miss. The layout fit looks up the (2 r + 1)^3 neighbours of every
// furniture candidate and files a million points into voxels; with the node map those
// took 0.12 s and a tenth of the fit on a 10 x 19 m courtyard's cloud (330 000 voxels).
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace room_reverb::core::layout {

class CellIndex {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  // Room for `expected` cells before the table grows.
  explicit CellIndex(std::size_t expected = 0) { rehash(expected); }

  // The index filed under `cell`, or kNone.
  std::uint32_t find(const Eigen::Vector3i& cell) const {
    const std::uint64_t k = pack(cell);
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (slots_[i].second == kNone || slots_[i].first == k) return slots_[i].second;
    }
  }

  // Files `index` under `cell` unless the cell has one: returns the cell's index and
  // whether it was filed now.
  std::pair<std::uint32_t, bool> insert(const Eigen::Vector3i& cell, std::uint32_t index) {
    if (2 * (size_ + 1) > slots_.size()) rehash(2 * slots_.size());
    const std::uint64_t k = pack(cell);
    std::size_t i = slot(k);
    for (; slots_[i].second != kNone; i = (i + 1) & mask_) {
      if (slots_[i].first == k) return {slots_[i].second, false};
    }
    slots_[i] = {k, index};
    ++size_;
    return {index, true};
  }

  std::size_t size() const { return size_; }

 private:
  // 21 bits per axis, offset so that negative cells pack too: +-2^20 cells is +-52 km at
  // 5 cm, far beyond any range the fit takes.
  static std::uint64_t pack(const Eigen::Vector3i& cell) {
    const auto bits = [](int c) { return static_cast<std::uint64_t>(c + (1 << 20)) & 0x1fffffu; };
    return bits(cell.x()) | (bits(cell.y()) << 21) | (bits(cell.z()) << 42);
  }
  // The product's top bits, which every bit of the key moves.
  std::size_t slot(std::uint64_t k) const { return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_); }

  // At most half full: short probe runs.
  void rehash(std::size_t cells) {
    std::size_t slots = 16;
    int shift = 60;
    while (slots < 2 * cells) slots *= 2, --shift;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> old(slots, {0, kNone});
    old.swap(slots_);
    mask_ = slots - 1;
    shift_ = shift;
    for (const auto& [k, index] : old) {
      if (index == kNone) continue;
      std::size_t i = slot(k);
      while (slots_[i].second != kNone) i = (i + 1) & mask_;
      slots_[i] = {k, index};
    }
  }

  std::vector<std::pair<std::uint64_t, std::uint32_t>> slots_;
  std::size_t mask_ = 0;
  int shift_ = 60;
  std::size_t size_ = 0;
};

}  // namespace room_reverb::core::layout
