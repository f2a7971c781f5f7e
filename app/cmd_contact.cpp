// `roverlab scenario fl-bogie-rotation|rear-bogie-rotation|bump-crossing` and
// `roverlab estimate contact-angle` (seed 000).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/log_input.h"
#include "app/views_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/contact_angle.h"
#include "core/simulation/flying_rover.h"
#include "importers/hdf5_log.h"
#include "importers/rover_file.h"

namespace roverlab::app {

using nlohmann::json;

namespace {

kinematics::RoverModel dh_rover(const std::string& name) {
  const io::RoverDescription d = io::find_rover(name, resource_subfolders("rovers"));
  if (!d.dh) throw InputError(d.file, "rover '" + d.name + "' is not described by a DH table (kind " + d.kind + ")");
  return *d.dh;
}

}  // namespace

int run_scenario_flying_rover(const FlyingRoverOptions& o) {
  const kinematics::RoverModel rover = dh_rover(o.rover);
  simulation::FlyingRoverScenario s;
  try {
    s = simulation::flying_rover_scenario(o.scenario, rover);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  s.seed = o.seed;
  if (!(o.rate >= 10.0 && o.rate <= 10000.0)) throw UsageError("--rate must be 10..10000 Hz");
  s.rate = o.rate;
  const log::Log lg = simulation::simulate_flying_rover(rover, s);
  io::write_hdf5_log(lg, o.output);
  std::printf("wrote %s: scenario %s, rover %s, %.0f s at %.0f Hz, seed %u\n", o.output.c_str(), o.scenario.c_str(),
              rover.name.c_str(), s.duration, s.rate, s.seed);
  return kSuccess;
}

int run_estimate_contact_angle(const ContactAngleCommandOptions& o) {
  estimation::ContactAngleOptions options;
  try {
    options.model = estimation::parse_contact_model(o.model);
    options.filter = estimation::parse_filter_kind(o.filter);
    options.angle_model = estimation::parse_angle_model(o.angle_model);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  options.reset_cross_covariance = o.reset_cross_covariance;
  if (o.process_noise == "imu") {
    options.attitude_variance = options.velocity_variance = 1e-12;
  } else if (o.process_noise != "seed") {
    throw UsageError("--process-noise " + o.process_noise + ": expected seed or imu");
  }
  options.joint_rate_window = o.joint_rate_window;
  if (o.velocity_variance) options.velocity_variance = *o.velocity_variance;
  if (o.attitude_variance) options.attitude_variance = *o.attitude_variance;
  if (o.slip_variance) options.slip_variance = *o.slip_variance;
  if (o.angle_variance) options.angle_variance = *o.angle_variance;
  const log::Log lg = load_input(o.file, o.mapping).log;
  const std::string rover_name = o.rover ? *o.rover : rover_name_of(lg);
  const kinematics::RoverModel rover = dh_rover(rover_name);
  if (isatty(2)) {
    options.progress = [](double f) { std::fprintf(stderr, "\rcontact-angle %3d %%", static_cast<int>(100 * f)); };
  }
  const auto start = std::chrono::steady_clock::now();
  estimation::ContactAngleResult r;
  try {
    r = estimation::run_contact_angle(lg, rover, options);
  } catch (const DataError& e) {
    throw InputError(o.file, e.what());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.progress) std::fprintf(stderr, "\r                    \r");
  if (o.output) {
    log::Log out = lg;
    for (const auto& s : r.estimates.streams()) out.add_stream(s);
    io::write_hdf5_log(out, *o.output);
  }
  const double deg = 180.0 / M_PI;
  std::vector<std::string> names;
  for (const auto& w : rover.wheels) names.push_back(w.name);
  if (o.json) {
    json j = {{"file", o.file}, {"rover", rover.name}, {"model", o.model}, {"filter", o.filter},
              {"angle_model", o.angle_model}, {"reset_cross_covariance", o.reset_cross_covariance},
              {"process_noise", o.process_noise},
              {"seconds", r.seconds}, {"wall_seconds", wall}, {"standstill_samples", r.standstill_samples},
              {"max_cross_correlation", r.max_cross_correlation}, {"wheels", names}, {"has_truth", r.has_truth}};
    if (r.has_truth) {
      json rms = {{"velocity_mps", r.rms.velocity}, {"slip", r.rms.slip}, {"samples", r.rms.samples}};
      std::vector<double> ca, ss;
      for (double v : r.rms.contact_angle) ca.push_back(v * deg);
      for (double v : r.rms.side_slip) ss.push_back(v * deg);
      if (!ca.empty()) rms["contact_angle_deg"] = ca;
      if (!ss.empty()) rms["side_slip_deg"] = ss;
      j["rms"] = rms;
    }
    if (o.output) j["output"] = *o.output;
    std::cout << j.dump(2) << "\n";
    return kSuccess;
  }
  std::printf("%s: rover %s, model %s, %s, %s angles%s; %.1f s of log in %.2f s\n", o.file.c_str(), rover.name.c_str(),
              o.model.c_str(), o.filter.c_str(), o.angle_model.c_str(),
              o.reset_cross_covariance ? ", cross-covariances reset" : "", r.seconds, wall);
  if (r.standstill_samples > 0) std::printf("standstill: %zu samples held and left out\n", r.standstill_samples);
  if (r.has_truth) {
    std::printf("\nRMS errors over %zu moving samples (layout of seed 000 Tables 6.2-6.5):\n", r.rms.samples);
    std::printf("  %-6s %14s %12s %16s %16s\n", "", "velocity (m/s)", "slip (-)", "contact (deg)", "side slip (deg)");
    const char* axes[3] = {"x", "y", "z"};
    for (std::size_t w = 0; w < 6; ++w) {
      char vel[32] = "";
      if (w < 3) std::snprintf(vel, sizeof vel, "%s %.4f", axes[w], r.rms.velocity[w]);
      char ca[32] = "-", ss[32] = "-";
      if (!r.rms.contact_angle.empty()) std::snprintf(ca, sizeof ca, "%.4f", r.rms.contact_angle[w] * deg);
      if (!r.rms.side_slip.empty()) std::snprintf(ss, sizeof ss, "%.4f", r.rms.side_slip[w] * deg);
      std::printf("  %-6s %14s %12.4f %16s %16s\n", names[w].c_str(), vel, r.rms.slip[w], ca, ss);
    }
  } else {
    std::printf("no truth streams: no errors\n");
  }
  std::printf("largest cross-correlation in P at the end: %.3f\n", r.max_cross_correlation);
  if (o.output) std::printf("wrote %s\n", o.output->c_str());
  return kSuccess;
}

}  // namespace roverlab::app
