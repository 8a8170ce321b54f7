#include "room_reverb/ros/simulation_server.h"

#include <cmath>
#include <limits>
#include <optional>

#include "room_reverb/common/error.h"
#include "room_reverb/ros/parameters.h"
#include "room_reverb/metrics/impulse_response_metrics.h"
#include "room_reverb/ros/audio_conversions.h"
#include "room_reverb/ros/room_conversions.h"

namespace room_reverb::ros_bridge {

SimulationServer::SimulationServer(::ros::NodeHandle& private_nh) {
  std::string mode, materials_file;
  typedParam(private_nh, "default_mode", mode, std::string("accurate"));
  defaults_.mode = core::parseSimulationMode(mode);
  defaults_.image_source_order = positiveIntParam(private_nh, "image_source_order", 3);
  defaults_.rays.ray_count = static_cast<std::size_t>(positiveIntParam(private_nh, "rays", 100000));
  defaults_.fast_ray_count = static_cast<std::size_t>(positiveIntParam(private_nh, "fast_rays", 64000));
  typedParam(private_nh, "fast_rate_tolerance", defaults_.fast_rays.rate_tolerance, defaults_.fast_rays.rate_tolerance);
  if (!(defaults_.fast_rays.rate_tolerance >= 0.0 && defaults_.fast_rays.rate_tolerance < 1.0)) {
    throw core::InputError("parameter ~fast_rate_tolerance must be 0 (a fixed ray count) or a share below 1");
  }
  typedParam(private_nh, "fast_reflection_budget", defaults_.fast_rays.reflection_budget, defaults_.fast_rays.reflection_budget);
  if (!(defaults_.fast_rays.reflection_budget > 0.0 && std::isfinite(defaults_.fast_rays.reflection_budget))) {
    throw core::InputError("parameter ~fast_reflection_budget must be a positive number of reflections");
  }
  typedParam(private_nh, "fast_track_radius", defaults_.fast_rays.track_radius_m, defaults_.fast_rays.track_radius_m);
  if (!(defaults_.fast_rays.track_radius_m > 0.0 && defaults_.fast_rays.track_radius_m <= 100.0)) {
    throw core::InputError("parameter ~fast_track_radius must be a positive number of metres (at most 100)");
  }
  typedParam(private_nh, "fast_launch_mixture", defaults_.fast_rays.late_launch_mixture,
             defaults_.fast_rays.late_launch_mixture);
  if (!(defaults_.fast_rays.late_launch_mixture >= 0.0 && defaults_.fast_rays.late_launch_mixture <= 0.9)) {
    throw core::InputError("parameter ~fast_launch_mixture must be a share from 0 to 0.9");
  }
  max_rays_ = positiveIntParam(private_nh, "max_rays", 10000000);
  if (defaults_.rays.ray_count > static_cast<std::size_t>(max_rays_) ||
      defaults_.fast_ray_count > static_cast<std::size_t>(max_rays_)) {
    throw core::InputError("parameters ~rays and ~fast_rays must not exceed ~max_rays (" + std::to_string(max_rays_) + ")");
  }
  defaults_.rays.seed = static_cast<std::uint32_t>(positiveIntParam(private_nh, "seed", 1));
  typedParam(private_nh, "threads", defaults_.rays.threads, 0);
  typedParam(private_nh, "ambisonic_order", defaults_.ambisonic_order, 1);
  if (defaults_.ambisonic_order < 0 || defaults_.ambisonic_order > 3) throw core::InputError("parameter ~ambisonic_order must be 0 to 3");
  typedParam(private_nh, "duration_s", defaults_.duration_s, 2.0);
  if (!(defaults_.duration_s > 0.0)) throw core::InputError("parameter ~duration_s must be positive");
  typedParam(private_nh, "receiver_radius_m", defaults_.rays.receiver_radius_m, 0.0);
  typedParam(private_nh, "continue_established_decays", defaults_.rays.continue_established_decays, true);
  typedParam(private_nh, "diffraction_scattering", defaults_.diffraction_scattering, false);
  std::string low_band;
  typedParam(private_nh, "low_band", low_band, std::string("geometric"));
  defaults_.low_band = core::parseLowBandMethod(low_band);
  typedParam(private_nh, "crossover_hz", defaults_.wave.crossover_hz, 500.0);
  std::string bands;
  typedParam(private_nh, "bands", bands, std::string("octave"));
  defaults_.bands = core::parseBandResolution(bands);
  if (!(defaults_.wave.crossover_hz >= 63.0 && defaults_.wave.crossover_hz <= 2000.0)) {
    throw core::InputError("parameter ~crossover_hz must be 63 to 2000 Hz");
  }
  typedParam(private_nh, "materials_file", materials_file, std::string(""));
  library_ = materials_file.empty() ? core::MaterialLibrary::loadDefault() : core::MaterialLibrary::load(materials_file);
  server_ = private_nh.advertiseService("simulate", &SimulationServer::simulate, this);
  job_server_ = private_nh.advertiseService("simulate_job", &SimulationServer::simulateJob, this);
}

bool SimulationServer::simulateJob(room_reverb::SimulateJob::Request& request, room_reverb::SimulateJob::Response& response) {
  response = room_reverb::SimulateJob::Response();
  try {
    const core::JobParts parts = core::splitJob(request.job.data(), request.job.size());
    const core::SimulationSettings& s = parts.request.settings;
    const std::size_t rays = s.mode == core::SimulationMode::kFast ? s.fast_ray_count : s.rays.ray_count;
    if (rays > static_cast<std::size_t>(max_rays_)) {
      throw core::InputError("rays: " + std::to_string(rays) + " is more than this node's ~max_rays (" +
                             std::to_string(max_rays_) + "); raise ~max_rays to allow it");
    }
    std::lock_guard<std::mutex> lock(job_mutex_);
    response.result = executor_.run(request.job.data(), request.job.size());
    response.success = true;
  } catch (const core::InputError& e) {
    response.message = e.what();
    response.input_error = true;
  } catch (const std::exception& e) {
    response.message = core::printableLine(std::string("room_simulator: ") + e.what());
  }
  return true;
}

bool SimulationServer::simulate(room_reverb::SimulateRoom::Request& request,
                                room_reverb::SimulateRoom::Response& response) {
  try {
    core::SimulationSettings settings = defaults_;
    if (!request.mode.empty()) settings.mode = core::parseSimulationMode(request.mode);
    if (request.image_source_order < 0 || request.rays < 0 || request.ambisonic_order < 0 || request.duration_s < 0.0) {
      throw core::InputError("image_source_order, rays, ambisonic_order and duration_s must not be negative (0: the node's default)");
    }
    if (request.rays > max_rays_) {
      // Refused up front: the count sets the time (the BRAS CR2 room: about 15 s for 10^5 rays
      // on two cores), and a caller's extra zeros would hold the node for hours.
      throw core::InputError("rays: " + std::to_string(request.rays) + " is more than this node's ~max_rays (" +
                             std::to_string(max_rays_) + "); raise ~max_rays to allow it");
    }
    if (request.image_source_order > 0) settings.image_source_order = request.image_source_order;
    if (request.rays > 0) {
      (settings.mode == core::SimulationMode::kFast ? settings.fast_ray_count : settings.rays.ray_count) =
          static_cast<std::size_t>(request.rays);
    }
    if (request.seed > 0) settings.rays.seed = static_cast<std::uint32_t>(request.seed);
    if (request.ambisonic_order > 0) settings.ambisonic_order = request.ambisonic_order;
    if (request.duration_s > 0.0) settings.duration_s = request.duration_s;

    core::MaterialOverrides overrides;
    if (request.global_scattering >= 0.0) overrides.global_scattering = request.global_scattering;
    std::optional<core::AcousticScene> scene;
    if (!request.mesh_file.empty()) {
      scene.emplace(core::loadMesh(request.mesh_file, request.mesh_y_up ? core::UpAxis::kY : core::UpAxis::kZ), library_,
                    overrides);
    } else {
      const core::RoomModel room = fromMessage(request.room);
      scene.emplace(core::roomModelToScene(room, library_, overrides));
      settings.air = room.air;
    }
    const Eigen::Vector3d source(request.source.x, request.source.y, request.source.z);
    const Eigen::Vector3d listener(request.listener.x, request.listener.y, request.listener.z);
    const core::SimulationResult result = core::simulateRoom(*scene, source, listener, settings);

    response.impulse_response.audio = toMessage(result.impulse_response, settings.ambisonic_order == 0 ? "mono" : "ambix");
    response.impulse_response.audio.header.frame_id = "room";
    response.impulse_response.audio.header.stamp = ::ros::Time::now();
    response.impulse_response.source_position = request.source;
    response.impulse_response.receiver_position = request.listener;
    response.impulse_response.positions_known = true;
    response.image_source_order = settings.image_source_order;
    if (request.late_part) {
      const core::AudioBuffer late = core::synthesizeLatePart(result, core::simulationSynthesisOptions(*scene, settings));
      response.late_impulse_response = response.impulse_response;
      response.late_impulse_response.audio = toMessage(late, settings.ambisonic_order == 0 ? "mono" : "ambix");
      response.late_impulse_response.audio.header = response.impulse_response.audio.header;
    }
    const core::MetricsReport metrics = core::analyseImpulseResponse(result.impulse_response, 0);
    for (const auto& band : metrics.bands) {
      response.t30_s.push_back(band.t30_s ? *band.t30_s : std::numeric_limits<double>::quiet_NaN());
    }
    response.eyring_t60_s.assign(result.eyring_t60_s.begin(), result.eyring_t60_s.end());
    response.leaked_rays = result.stats.leaked_rays;
    response.rays_traced = result.stats.rays;
    response.success = true;
  } catch (const std::exception& e) {
    response = room_reverb::SimulateRoom::Response();
    response.success = false;
    response.message = e.what();
  }
  return true;
}

}  // namespace room_reverb::ros_bridge
