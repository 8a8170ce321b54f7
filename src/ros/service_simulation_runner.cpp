#include "room_reverb/ros/service_simulation_runner.h"

#include <room_reverb/SimulateJob.h>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

ServiceSimulationRunner::ServiceSimulationRunner(std::vector<std::string> services, double wait_s)
    : services_(std::move(services)) {
  if (services_.empty()) throw core::InputError("simulators: no service name given");
  std::string missing;
  for (const std::string& name : services_) {
    if (!::ros::service::waitForService(name, ::ros::Duration(wait_s))) missing += (missing.empty() ? "" : ", ") + name;
  }
  if (!missing.empty()) {
    throw core::InputError("simulators: no service " + missing + " after " + std::to_string(wait_s) +
                           " s (start room_simulator there, or give the full name: /NODE/simulate_job)");
  }
  ::ros::NodeHandle nh;
  for (const std::string& name : services_) clients_.push_back(nh.serviceClient<room_reverb::SimulateJob>(name, true));
}

std::string ServiceSimulationRunner::description() const {
  return std::to_string(services_.size()) + " room_simulator node" + (services_.size() == 1 ? "" : "s");
}

core::RemoteSimulationRunner::Reply ServiceSimulationRunner::runOn(std::size_t slot, const std::vector<std::uint8_t>& job) {
  ::ros::ServiceClient& client = clients_[slot];
  // A persistent connection breaks when its node restarts: connect again once.
  if (!client.isValid()) client = ::ros::NodeHandle().serviceClient<room_reverb::SimulateJob>(services_[slot], true);
  room_reverb::SimulateJob srv;
  srv.request.job = job;
  Reply reply;
  if (!client.call(srv)) {
    reply.status = Reply::Status::kFailure;
    reply.message = "simulator " + services_[slot] + " did not answer (its node has gone?)";
    return reply;
  }
  if (srv.response.success) {
    reply.status = Reply::Status::kResult;
    reply.result = std::move(srv.response.result);
  } else {
    reply.status = srv.response.input_error ? Reply::Status::kInputError : Reply::Status::kFailure;
    reply.message = srv.response.message;
  }
  return reply;
}

}  // namespace room_reverb::ros_bridge
