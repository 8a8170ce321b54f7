#pragma once
// The checks and the output length every renderer of an RSAO shares (resynthesizeRsao,
// renderRsaoBinaural), so that they accept the same objects and play them for as long.
#include <cstddef>
#include <string>

#include "room_reverb/rsao/rsao.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace room_reverb::core {

// Throws InputError, its message starting with `context`, for an Rsao no renderer can play
// (non-finite or negative times or levels, a non-finite direction, a late part whose band
// count is not nine, a non-positive decay constant, an onset after the mixing time) or
// options out of range (analysis_window_s or match_bandwidths not positive, negative
// reflection_response_s or match_passes).
void checkRenderInput(const Rsao& rsao, const ResynthesisOptions& options, const std::string& context);

// The output's length in samples at 48 kHz: options.duration_s; when 0, Rsao::duration_s;
// when that is 0 too, the mixing time plus the longest band T60 (or the last reflection's
// response, if later). InputError beyond 60 s.
std::size_t renderFrameCount(const Rsao& rsao, const ResynthesisOptions& options, const std::string& context);

}  // namespace room_reverb::core
