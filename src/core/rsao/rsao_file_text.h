#pragma once
// Numbers in the RSAO files (rsao_yaml, rsao_visr_json): private to those two writers.
#include <string>

namespace room_reverb::core::rsao_text {

// The shortest decimal that reads back as exactly `value` (std::to_chars); YAML's .inf,
// -.inf and .nan for the non-finite.
std::string shortestDecimal(double value);

// Angles are radians in code and degrees in files. Degrees are chosen so that the text
// round trip is exact: radians -> file degrees -> radians -> file degrees gives the same
// degrees again (and, where some double of degrees maps onto the radians exactly, the same
// radians too). Plain r * 180 / pi would drift by an ulp now and then.
double fileDegrees(double radians);
double radiansFromFileDegrees(double degrees);

}  // namespace room_reverb::core::rsao_text
