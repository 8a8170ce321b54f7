// HrtfSet::loadSofa: SimpleFreeFieldHRIR files (AES69) through libmysofa.
#include "room_reverb/binaural/hrtf_set.h"

#include <mysofa.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "hrir_timing.h"
#include "room_reverb/audio/resample.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

constexpr char kConvention[] = "SimpleFreeFieldHRIR";
// Delays (Data.Delay, samples) below this are rounding noise, not delays to apply.
constexpr double kNegligibleDelaySamples = 1e-6;

struct SofaDeleter {
  void operator()(MYSOFA_HRTF* hrtf) const { mysofa_free(hrtf); }
};
using SofaPtr = std::unique_ptr<MYSOFA_HRTF, SofaDeleter>;

std::string describeError(int code) {
  switch (code) {
    case MYSOFA_INVALID_FORMAT: return "not an HDF5/netCDF-4 file, or a damaged one";
    case MYSOFA_UNSUPPORTED_FORMAT: return "an HDF5 layout libmysofa cannot read";
    case MYSOFA_NO_MEMORY: return "out of memory";
    case MYSOFA_READ_ERROR: return "the file ends early or cannot be read";
    case MYSOFA_INVALID_ATTRIBUTES: return "missing or wrong SOFA attributes";
    case MYSOFA_INVALID_DIMENSIONS: return "variables of inconsistent dimensions";
    case MYSOFA_INVALID_DIMENSION_LIST: return "a wrong DIMENSION_LIST";
    case MYSOFA_INVALID_COORDINATE_TYPE: return "an unknown coordinate type";
    case MYSOFA_ONLY_EMITTER_WITH_ECI_SUPPORTED: return "emitter positions not of size E,C,I";
    case MYSOFA_ONLY_DELAYS_WITH_IR_OR_MR_SUPPORTED: return "delays not of size I,R or M,R";
    case MYSOFA_ONLY_THE_SAME_SAMPLING_RATE_SUPPORTED: return "more than one sampling rate";
    case MYSOFA_RECEIVERS_WITH_RCI_SUPPORTED: return "receiver positions not of size R,C,I";
    case MYSOFA_RECEIVERS_WITH_CARTESIAN_SUPPORTED: return "receiver positions not cartesian";
    case MYSOFA_INVALID_RECEIVER_POSITIONS: return "receiver positions that are not two ears";
    case MYSOFA_ONLY_SOURCES_WITH_MC_SUPPORTED: return "source positions not of size M,C";
    default: return "libmysofa error " + std::to_string(code);
  }
}

std::string attribute(MYSOFA_ATTRIBUTE* attributes, const char* name) {
  for (MYSOFA_ATTRIBUTE* a = attributes; a; a = a->next) {
    if (a->name && a->value && std::string(a->name) == name) return a->value;
  }
  return "";
}

SofaPtr openChecked(const std::string& path) {
  const std::string what = "HRTF file '" + path + "'";
  requireExistingFile(path, "SOFA HRTF file");
  int error = MYSOFA_OK;
  SofaPtr sofa(mysofa_load(path.c_str(), &error));
  if (!sofa || error != MYSOFA_OK) {
    throw InputError(what + " is not a readable SOFA file (" + describeError(error) +
                     "): give a SOFA file of the " + kConvention + " convention");
  }
  // The convention first, so that another one is named as such rather than reported as
  // whatever check below it happens to fail.
  const std::string convention = attribute(sofa->attributes, "SOFAConventions");
  if (convention != kConvention) {
    throw InputError(what + " uses the SOFA convention '" + convention + "'; only " +
                     kConvention + " HRIRs can be read");
  }
  if (sofa->R != 2) {
    throw InputError(what + " has " + std::to_string(sofa->R) +
                     " receivers; an HRTF set needs exactly 2 (left and right ear)");
  }
  error = mysofa_check(sofa.get());
  if (error != MYSOFA_OK) {
    throw InputError(what + " is not a valid " + kConvention + " file (" +
                     describeError(error) + ")");
  }
  const unsigned values = sofa->M * sofa->R * sofa->N;
  if (sofa->N == 0 || sofa->M == 0 || sofa->DataIR.elements != values ||
      sofa->SourcePosition.elements != sofa->M * 3 || sofa->DataSamplingRate.elements != 1) {
    throw InputError(what + " has inconsistent data sizes");
  }
  if (!std::all_of(sofa->DataIR.values, sofa->DataIR.values + values,
                   [](float v) { return std::isfinite(v); })) {
    throw InputError(what + " contains NaN or infinite HRIR samples");
  }
  return sofa;
}

// The listener must look along +x for the source positions to be head-frame directions.
void checkListenerView(const MYSOFA_HRTF& sofa, const std::string& path) {
  if (sofa.ListenerView.elements != 3) return;
  const Eigen::Vector3d view(sofa.ListenerView.values[0], sofa.ListenerView.values[1],
                             sofa.ListenerView.values[2]);
  if (!(view.normalized().x() > 0.9999)) {
    throw InputError("HRTF file '" + path +
                     "' has a ListenerView other than +x; such files are not supported");
  }
}

// Data.Delay of each ear (samples, per measurement or one for all); SimpleFreeFieldHRIR
// files usually carry zeros with the delay inside the HRIRs.
double dataDelay(const MYSOFA_HRTF& sofa, unsigned measurement, unsigned receiver) {
  const MYSOFA_ARRAY& delay = sofa.DataDelay;
  if (delay.elements == sofa.M * sofa.R) return delay.values[measurement * sofa.R + receiver];
  if (delay.elements == sofa.R) return delay.values[receiver];
  return 0.0;
}

// Builds the pairs; applies Data.Delay when any is non-zero by lengthening the HRIRs.
std::vector<Hrir> readHrirs(const MYSOFA_HRTF& sofa, std::vector<std::string>& notes) {
  double max_delay = 0.0;
  for (unsigned m = 0; m < sofa.M; ++m) {
    for (unsigned r = 0; r < 2; ++r) max_delay = std::max(max_delay, dataDelay(sofa, m, r));
  }
  const std::size_t n = sofa.N;
  const bool delayed = max_delay > kNegligibleDelaySamples;
  const std::size_t out_length = n + static_cast<std::size_t>(std::ceil(delayed ? max_delay : 0.0));
  hrir_timing::DelayingSum shifter(n, out_length);
  std::vector<Hrir> hrirs(sofa.M);
  for (unsigned m = 0; m < sofa.M; ++m) {
    for (unsigned r = 0; r < 2; ++r) {
      const float* begin = sofa.DataIR.values + (static_cast<std::size_t>(m) * 2 + r) * n;
      std::vector<float> ir(begin, begin + n);
      if (delayed) {
        shifter.add(ir, 1.0, dataDelay(sofa, m, r));
        ir = shifter.take();
      }
      (r == 0 ? hrirs[m].left : hrirs[m].right) = std::move(ir);
    }
  }
  if (delayed) {
    std::ostringstream os;
    os << "applied the file's Data.Delay (up to " << max_delay << " samples) to the HRIRs";
    notes.push_back(os.str());
  }
  return hrirs;
}

// Resampled a few dozen pairs per converter run: several channels share the sinc
// coefficients (faster than pair by pair), and libsamplerate takes at most 128 channels.
void resampleHrirs(std::vector<Hrir>& hrirs, double from_hz, double to_hz,
                   std::vector<std::string>& notes) {
  constexpr std::size_t kPairsPerRun = 32;
  const std::size_t before = hrirs.front().left.size();
  for (std::size_t first = 0; first < hrirs.size(); first += kPairsPerRun) {
    const std::size_t end = std::min(hrirs.size(), first + kPairsPerRun);
    AudioBuffer chunk;
    chunk.sample_rate_hz = from_hz;
    for (std::size_t i = first; i < end; ++i) {
      chunk.channels.push_back(std::move(hrirs[i].left));
      chunk.channels.push_back(std::move(hrirs[i].right));
    }
    AudioBuffer out = resample(chunk, to_hz);
    for (std::size_t i = first; i < end; ++i) {
      hrirs[i].left = std::move(out.channels[2 * (i - first)]);
      hrirs[i].right = std::move(out.channels[2 * (i - first) + 1]);
    }
  }
  std::ostringstream os;
  os << "resampled from " << from_hz << " Hz to " << to_hz << " Hz (" << before << " -> "
     << hrirs.front().left.size() << " taps)";
  notes.push_back(os.str());
}

// SOFA puts the left ear first. Some files (the FHK KU100 sets among them) give the first
// receiver a position on the right although its data is the left ear's; the data wins,
// and the note records the mismatch.
void noteReceiverPositions(const MYSOFA_HRTF& sofa, std::vector<std::string>& notes) {
  if (sofa.ReceiverPosition.elements < 6) return;
  if (sofa.ReceiverPosition.values[1] < sofa.ReceiverPosition.values[4]) {
    notes.push_back(
        "the file places the first receiver right of the second; kept the SOFA order "
        "(first = left ear)");
  }
}

std::string describe(MYSOFA_HRTF* sofa, const std::string& path) {
  std::string text = attribute(sofa->attributes, "DatabaseName");
  const std::string listener = attribute(sofa->attributes, "ListenerShortName");
  if (!listener.empty()) text += (text.empty() ? "" : " ") + listener;
  const std::string file = std::filesystem::path(path).filename().string();
  return text.empty() ? file : text + " (" + file + ")";
}

}  // namespace

HrtfSet HrtfSet::loadSofa(const std::string& path, double target_rate_hz) {
  SofaPtr sofa = openChecked(path);
  mysofa_tocartesian(sofa.get());
  checkListenerView(*sofa, path);

  std::vector<Eigen::Vector3d> directions;
  directions.reserve(sofa->M);
  double min_distance = INFINITY;
  double max_distance = 0.0;
  for (unsigned m = 0; m < sofa->M; ++m) {
    const float* p = sofa->SourcePosition.values + 3 * m;
    const Eigen::Vector3d position(p[0], p[1], p[2]);
    const double distance = position.norm();
    if (!std::isfinite(distance) || distance == 0.0) {
      throw InputError("HRTF file '" + path + "': source position " + std::to_string(m) +
                       " is at the listener or not finite");
    }
    min_distance = std::min(min_distance, distance);
    max_distance = std::max(max_distance, distance);
    directions.push_back(position / distance);
  }

  std::vector<std::string> notes;
  noteReceiverPositions(*sofa, notes);
  std::vector<Hrir> hrirs = readHrirs(*sofa, notes);
  const double file_rate = sofa->DataSamplingRate.values[0];
  if (!(file_rate >= kMinSampleRateHz && file_rate <= kMaxSampleRateHz)) {
    throw InputError("HRTF file '" + path + "' has an unusable sampling rate of " +
                     std::to_string(file_rate) + " Hz");
  }
  if (file_rate != target_rate_hz) resampleHrirs(hrirs, file_rate, target_rate_hz, notes);
  std::ostringstream distances;
  distances << "source distances " << min_distance << ".." << max_distance
            << " m, kept as directions only";
  notes.push_back(distances.str());

  HrtfSet set(target_rate_hz, std::move(directions), std::move(hrirs), describe(sofa.get(), path));
  set.notes_ = std::move(notes);
  return set;
}

std::string HrtfSet::defaultSofaPath() {
  return packageFilePath("ROOM_REVERB_HRTF", "data/hrtf/FHK_HRIR_L2354.sofa");
}

}  // namespace room_reverb::core
