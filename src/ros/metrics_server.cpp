#include "room_reverb/ros/parameters.h"
#include "room_reverb/ros/metrics_server.h"

#include <limits>

#include "room_reverb/common/error.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/ros/audio_conversions.h"

namespace room_reverb::ros_bridge {
namespace {

double valueOrNan(const std::optional<double>& value) {
  return value ? *value : std::numeric_limits<double>::quiet_NaN();
}

room_reverb::BandMetrics toMessage(const core::AcousticParameters& p) {
  room_reverb::BandMetrics msg;
  msg.nominal_center_hz = p.nominal_hz;
  msg.center_hz = p.center_hz;
  msg.t20_s = valueOrNan(p.t20_s);
  msg.t30_s = valueOrNan(p.t30_s);
  msg.edt_s = valueOrNan(p.edt_s);
  msg.c50_db = valueOrNan(p.c50_db);
  msg.c80_db = valueOrNan(p.c80_db);
  msg.d50 = valueOrNan(p.d50);
  msg.ts_s = valueOrNan(p.ts_s);
  msg.drr_db = valueOrNan(p.drr_db);
  msg.decay_range_db = p.decay_range_db;
  msg.reliable = p.reliable;
  msg.reason = p.reason;
  return msg;
}

}  // namespace

MetricsServer::MetricsServer(::ros::NodeHandle& private_nh) {
  typedParam(private_nh, "default_bands", default_bands_, std::string("octave"));
  // Fail at start, loudly, rather than at the first call.
  core::parseBandResolution(default_bands_);
  server_ = private_nh.advertiseService("compute_metrics", &MetricsServer::compute, this);
}

bool MetricsServer::compute(room_reverb::ComputeMetrics::Request& request,
                            room_reverb::ComputeMetrics::Response& response) {
  try {
    const core::AudioBuffer rir = fromMessage(request.impulse_response.audio);
    core::MetricsOptions options;
    options.resolution =
        core::parseBandResolution(request.bands.empty() ? default_bands_ : request.bands);
    const core::MetricsReport report =
        core::analyseImpulseResponse(rir, static_cast<int>(request.channel), options);
    response.onset_s = report.onset_s;
    for (const auto& band : report.bands) response.bands.push_back(toMessage(band));
    response.broadband = toMessage(report.broadband);
    response.success = true;
  } catch (const std::exception& e) {
    response = room_reverb::ComputeMetrics::Response();
    response.success = false;
    response.message = e.what();
  }
  // The call itself succeeded; success=false carries the input error to the caller.
  return true;
}

}  // namespace room_reverb::ros_bridge
