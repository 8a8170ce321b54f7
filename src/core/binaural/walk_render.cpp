#include "room_reverb/binaural/walk_render.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/binaural/binaural_stream.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace room_reverb::core {
namespace {

constexpr const char* kPoseHeader = "t_s,x_m,y_m,z_m,qx,qy,qz,qw";
constexpr std::size_t kBlock = 256;

std::string trimmed(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

}  // namespace

std::vector<ListenerPose> parsePoseCsv(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  std::size_t number = 0;
  std::vector<ListenerPose> poses;
  bool header = false;
  while (std::getline(lines, line)) {
    ++number;
    line = trimmed(line);
    if (line.empty()) continue;
    const std::string where = "pose file line " + std::to_string(number);
    if (!header) {
      std::string compact;
      for (char c : line) {
        if (c != ' ' && c != '\t') compact += c;
      }
      if (compact != kPoseHeader) throw InputError(where + ": the header must be " + kPoseHeader + ", got '" + line + "'");
      header = true;
      continue;
    }
    std::vector<double> v;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) {
      cell = trimmed(cell);
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0') throw InputError(where + ": '" + cell + "' is not a number");
      if (!std::isfinite(x)) throw InputError(where + ": '" + cell + "' is not finite");
      v.push_back(x);
    }
    if (v.size() != 8) throw InputError(where + ": 8 values expected (" + kPoseHeader + "), got " + std::to_string(v.size()));
    ListenerPose pose;
    pose.t_s = v[0];
    pose.position_m = {v[1], v[2], v[3]};
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (q.norm() < 1e-9) throw InputError(where + ": the orientation quaternion has zero length");
    pose.orientation = q.normalized();
    if (!poses.empty() && !(pose.t_s > poses.back().t_s)) {
      throw InputError(where + ": times must increase (" + std::to_string(pose.t_s) + " s after " +
                       std::to_string(poses.back().t_s) + " s)");
    }
    poses.push_back(pose);
  }
  if (!header) throw InputError(std::string("pose file: empty; it needs the header ") + kPoseHeader + " and a row");
  if (poses.empty()) throw InputError("pose file: no pose after the header");
  return poses;
}

std::vector<ListenerPose> loadPoseCsv(const std::string& path) {
  const std::string text = readTextFile(path, "pose file");
  try {
    return parsePoseCsv(text);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

ListenerPose poseAt(const std::vector<ListenerPose>& poses, double t_s) {
  if (t_s <= poses.front().t_s) return poses.front();
  if (t_s >= poses.back().t_s) return poses.back();
  const auto after = std::upper_bound(poses.begin(), poses.end(), t_s,
                                      [](double t, const ListenerPose& p) { return t < p.t_s; });
  const ListenerPose& b = *after;
  const ListenerPose& a = *(after - 1);
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  ListenerPose pose;
  pose.t_s = t_s;
  pose.position_m = a.position_m + u * (b.position_m - a.position_m);
  pose.orientation = a.orientation.slerp(u, b.orientation);
  return pose;
}

std::vector<TapTarget> tapTargetsAt(const ListenerTranslation& translation, const Eigen::Vector3d& listener_m) {
  std::vector<MovedArrival> arrivals;
  translation.arrivalsAt(listener_m, arrivals);
  std::vector<TapTarget> targets;
  targets.reserve(arrivals.size());
  for (const MovedArrival& a : arrivals) targets.push_back({a.time_of_arrival_s, a.heard ? a.level : 0.0, a.direction, a.lowpass_pole});
  return targets;
}

void tapTargetsBetween(const std::vector<TapTarget>& from, const std::vector<TapTarget>& to, double u,
                       std::vector<TapTarget>& out) {
  out.resize(to.size());
  if (from.size() != to.size()) {
    std::copy(to.begin(), to.end(), out.begin());
    return;
  }
  for (std::size_t k = 0; k < to.size(); ++k) {
    const TapTarget& a = from[k];
    const TapTarget& b = to[k];
    TapTarget& t = out[k];
    t.delay_s = a.delay_s + u * (b.delay_s - a.delay_s);
    t.level = a.level + u * (b.level - a.level);
    t.lowpass_pole = a.lowpass_pole + u * (b.lowpass_pole - a.lowpass_pole);
    const Eigen::Vector3d blend = (1.0 - u) * a.direction + u * b.direction;
    const double length = blend.norm();
    t.direction = length > 1e-6 ? Eigen::Vector3d(blend / length) : b.direction;
  }
}

void ChunkedTapTargets::place(std::vector<TapTarget> targets) {
  from_ = std::move(targets);
  to_.clear();
}

void ChunkedTapTargets::beginChunk(std::vector<TapTarget> targets, std::size_t blocks) {
  to_ = std::move(targets);
  blocks_ = std::max<std::size_t>(1, blocks);
}

const std::vector<TapTarget>& ChunkedTapTargets::atBlock(std::size_t b) {
  tapTargetsBetween(from_, to_, static_cast<double>(std::min(b + 1, blocks_)) / static_cast<double>(blocks_), now_);
  return now_;
}

void ChunkedTapTargets::endChunk() { std::swap(from_, to_); }

namespace {

// Streams `dry` and `tail_frames` of silence through `stream` block by block, the head
// turned to each block's pose (the pose at its end); `before_block(b, pose)` moves the
// room first. Left and right, the dry sound's length plus the tail.
AudioBuffer streamWalk(const AudioBuffer& dry, std::size_t tail_frames, BinauralStream& stream,
                       const std::vector<ListenerPose>& poses,
                       const std::function<void(std::size_t, const ListenerPose&)>& before_block) {
  const std::size_t frames = dry.frameCount() + tail_frames;
  const std::size_t blocks = (frames + kBlock - 1) / kBlock;
  AudioBuffer out = makeSilentBuffer(2, blocks * kBlock, kInternalSampleRateHz);
  std::vector<float> block(kBlock);
  for (std::size_t b = 0; b < blocks; ++b) {
    const ListenerPose pose = poseAt(poses, static_cast<double>((b + 1) * kBlock) / kInternalSampleRateHz);
    before_block(b, pose);
    stream.setHeadOrientation(pose.orientation);
    for (std::size_t n = 0; n < kBlock; ++n) {
      const std::size_t i = b * kBlock + n;
      block[n] = i < dry.frameCount() ? dry.channels[0][i] : 0.0f;
    }
    stream.process(block.data(), out.channels[0].data() + b * kBlock, out.channels[1].data() + b * kBlock);
  }
  for (auto& channel : out.channels) channel.resize(frames);
  return out;
}

}  // namespace

AudioBuffer renderWalk(const AudioBuffer& dry, const ListenerTranslation& translation, const BinauralDecoder& decoder,
                       const std::vector<ListenerPose>& poses, std::uint32_t seed) {
  if (poses.empty()) throw InputError("walk render: no pose");
  if (dry.channelCount() != 1 || dry.sample_rate_hz != kInternalSampleRateHz) {
    throw InputError("walk render: the dry source must be mono at 48000 Hz");
  }
  ResynthesisOptions late_only;
  late_only.seed = seed;
  late_only.include_early = false;
  Rsao late_part = translation.measured();
  late_part.late = translation.late();
  const AudioBuffer late = resynthesizeRsao(late_part, late_only);
  BinauralStreamOptions options;
  options.block_size = kBlock;
  options.max_response_s = std::max(late.durationS(), 0.01);
  BinauralStream stream(decoder, options);
  stream.setRoom(late);
  ReflectionTapBankOptions tap_options;
  tap_options.order = decoder.order;
  tap_options.block_size = kBlock;
  tap_options.max_delay_s = 1.0;
  stream.setEarlyTaps(std::make_unique<ReflectionTapBank>(translation.reflectionsAtRig(), tap_options));

  return streamWalk(dry, late.frameCount(), stream, poses, [&](std::size_t, const ListenerPose& pose) {
    // The pose at the end of the block: the taps glide to it across the block.
    stream.earlyTaps()->setTargets(tapTargetsAt(translation, pose.position_m));
  });
}

AudioBuffer renderSimulatedWalk(const AudioBuffer& dry, const SimulatedWalk& walk, const BinauralDecoder& decoder,
                                const std::vector<ListenerPose>& poses, std::size_t update_blocks) {
  if (poses.empty()) throw InputError("walk render: no pose");
  if (update_blocks == 0) throw InputError("walk render: update_blocks must be positive");
  if (dry.channelCount() != 1 || dry.sample_rate_hz != kInternalSampleRateHz) {
    throw InputError("walk render: the dry source must be mono at 48000 Hz");
  }
  for (const ListenerPose& pose : poses) walk.requireListener(pose.position_m);
  const AudioBuffer& late = walk.late();
  BinauralStreamOptions options;
  options.block_size = kBlock;
  options.max_response_s = std::max(late.durationS(), 0.01);
  options.early_crossfade_blocks = update_blocks;
  BinauralStream stream(decoder, options);
  stream.setRoom(late);

  return streamWalk(dry, late.frameCount(), stream, poses, [&](std::size_t b, const ListenerPose&) {
    // A new early part as often as a fade completes: where the listener will be half an
    // update later, so that the fade is centred on the pose it plays.
    if (b % update_blocks == 0) {
      const double centre_s = static_cast<double>(b * kBlock + update_blocks * kBlock / 2) / kInternalSampleRateHz;
      stream.setEarlyResponse(walk.earlyAt(poseAt(poses, centre_s).position_m));
    }
  });
}

}  // namespace room_reverb::core
