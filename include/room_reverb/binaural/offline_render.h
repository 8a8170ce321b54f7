#pragma once
// Offline binaural rendering: a dry source heard in a room, whole signals at once. The
// `render` tool and the binaural_renderer node's ~render_to_file share it; the streaming
// renderer (binaural_stream.h) computes the same signal block by block.
//
//   room response (any B-format convention, any rate)  --ambixRoomResponse-->  AmbiX, 48 kHz
//   --binauralRoomResponse (head rotation, decoder)-->  BRIR (left, right)
//   --convolveBinaural (with the mono source, peak kept under full scale)-->  binaural audio
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/binaural/binaural_decoder.h"

namespace room_reverb::core {

// A dry (anechoic) source as the renderers take it: every channel of the file mixed to one
// (mixToMono) at 48 kHz. A line goes to `notes` for each change made on the way (channels
// mixed, rate converted), for the caller to show. InputError as readAudioFile.
AudioBuffer loadDrySource(const std::string& path, std::vector<std::string>& notes);

// A room response as AmbiX (ACN/SN3D) at 48 kHz. `layout` says what the channels are:
// "fuma" (first-order FuMa: W X Y Z, 4 channels), "ambix" (order 0-3: 1, 4, 9 or 16
// channels) or "mono" (an omnidirectional response, order 0). Other rates are resampled and
// a note appended to `notes`. InputError for an unknown layout, a channel count the layout
// does not allow, or an invalid buffer (validateAudioBuffer: empty, non-finite...).
AudioBuffer ambixRoomResponse(const AudioBuffer& response, const std::string& layout, std::vector<std::string>& notes);

// The binaural room impulse response (left, right) of an AmbiX room response for a head
// in orientation `head_in_room` (rotation.h): the field is turned for the head, then
// decoded. A response of lower order than the decoder's is padded with silent channels (as
// the streaming renderer does); an order-0 response is heard as a first-order one with
// silent X, Y, Z. InputError for a response of higher order than the decoder, a decoder
// not at the response's rate, or a malformed quaternion.
AudioBuffer binauralRoomResponse(const AudioBuffer& ambix, const BinauralDecoder& decoder,
                                 const Eigen::Quaterniond& head_in_room);

// The order of the decoder an AmbiX room response goes through: its own order, but at least
// 1, since an omnidirectional (order-0) response has no directions to decode and is heard
// as a first-order one with silent X, Y, Z. InputError for a channel count that is no order.
int binauralDecoderOrder(const AudioBuffer& ambix);

struct BinauralRender {
  AudioBuffer audio;     // 2 channels, left and right
  double peak_dbfs = 0.0;  // after any gain
  double gain_db = 0.0;    // 0, or the negative gain that brought a peak above 0 dBFS to -1 dBFS
};

// The mono source convolved with each ear's response. A render for listening must not clip
// on a fixed-point player, so a peak above full scale is brought to -1 dBFS (gain_db says
// by how much). InputError for a source that is not mono or rates that differ.
BinauralRender convolveBinaural(const AudioBuffer& mono_source, const AudioBuffer& brir);

}  // namespace room_reverb::core
