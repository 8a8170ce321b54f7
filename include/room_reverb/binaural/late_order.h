#pragma once
// A mixed-order room response for the head-tracked stream: the response keeps all its
// ambisonic orders for `full_order_s`, and after it only orders 0 and 1, equalised so
// that the binaural decoder gives the diffuse part the same power spectrum at each ear.
//
// Why: the stream convolves the source with every channel of the room response, so a 2 s
// third-order room costs about twice a first-order one (bench_binaural_renderer); past the
// mixing time the field is close to diffuse, and listening tests find little or no gain
// from high orders there once the direct sound and early part keep theirs (Engel, Henry,
// Amengual Garí, Robinson and Picinali 2021, JASA 149(2), "hybrid Ambisonics"; Lübeck et
// al. found first order enough for diffuse reverberation with a MagLS decoder).
//
// How: over a 5.3 ms raised-cosine fade centred on full_order_s the orders above 1 fade
// out, and orders 0-1 fade to their equalised copy. The equaliser is a zero-phase FIR
// whose gain at each frequency is sqrt(P_all / P_01), P the decoder's diffuse-field power
// summed over both ears, over all channels or over orders 0-1 only (each ACN channel of
// order l carrying 1 / (2l + 1) of a diffuse field's power in SN3D). It restores the
// ears' spectrum; what the truncation changes is the interaural coherence of the late
// part at high frequencies (measured in test_late_order and docs/rendering.md).
#include <cstddef>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/binaural/binaural_decoder.h"

namespace room_reverb::core {

// The equaliser's taps (odd length, zero phase: tap (length - 1) / 2 is time 0) for a
// decoder of order 2 or more. Throws InputError for a decoder of order below 2.
std::vector<float> lateOrderEqualiser(const BinauralDecoder& decoder);

// The response (AmbiX at 48 kHz, order up to the decoder's) with its orders above 1 cut
// after full_order_s as above; orders above 1 are zero from full_order_s plus half the
// fade, which a partitioned convolver skips (it trims a filter's trailing zeros). A response of order 0 or 1, or one
// that ends before the fade, is returned unchanged. Throws InputError for a negative or
// non-finite full_order_s, a response of more orders than the decoder, or a decoder of
// order below 2 given a response of order 2 or 3.
AudioBuffer reduceLateOrder(const AudioBuffer& ambix, const BinauralDecoder& decoder, double full_order_s);

}  // namespace room_reverb::core
