#pragma once
// Conversions between the Rsao message and the core's Rsao.
#include <room_reverb/Rsao.h>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::ros_bridge {

room_reverb::Rsao toMessage(const core::Rsao& rsao);
// Throws core::InputError when the message is inconsistent (band arrays of different
// lengths, a sos array that is not a multiple of five, no direct sound).
core::Rsao fromMessage(const room_reverb::Rsao& msg);

}  // namespace room_reverb::ros_bridge
