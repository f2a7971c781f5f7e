// roverlab: command-line entry point. Exit codes: 0 success, 2 usage error,
// 3 bad input, 4 internal failure.
#include <CLI/CLI.hpp>
#include <iostream>

#include "app/commands.h"
#include "views/x_display.h"
#include "core/common/error.h"

#ifndef ROVERLAB_VERSION
#define ROVERLAB_VERSION "unknown"
#endif

namespace {

int dispatch(int argc, char** argv) {
  using namespace roverlab::app;
  CLI::App cli{"RoverLab: analysis and visualisation of planetary-rover field-test logs"};
  cli.require_subcommand(1);
  cli.set_version_flag("--version", ROVERLAB_VERSION);

  InfoOptions info;
  auto* info_cmd = cli.add_subcommand(
      "info", "List a log's streams and channels with units, sample counts, rates and durations");
  info_cmd->add_option("FILE", info.file, "Log file: RoverLab HDF5, MATLAB v7.3 (.mat) or CSV")
      ->required();
  info_cmd->add_option("--mapping,-m", info.mapping,
                       "Mapping NAME (resources/mappings/NAME.json) or FILE for .mat/HDF5 input");
  info_cmd->add_flag("--json", info.json, "Print JSON instead of text");

  ConvertOptions convert;
  auto* convert_cmd =
      cli.add_subcommand("convert", "Convert a log to a RoverLab HDF5 log (or a one-stream CSV)");
  convert_cmd->add_option("IN", convert.input, "Input log: HDF5, MATLAB v7.3 (.mat) or CSV")
      ->required();
  convert_cmd->add_option("OUT", convert.output, "Output file: .h5 / .hdf5, or .csv")->required();
  convert_cmd->add_option("--mapping,-m", convert.mapping,
                          "Mapping NAME (resources/mappings/NAME.json) or FILE for .mat/HDF5 input");

  convert_cmd->add_option("--stream,-s", convert.stream, "For .csv output: the stream to write");

  auto* mappings_cmd = cli.add_subcommand("mappings", "List the importer mappings RoverLab knows");

  // terramechanics: evaluate the wheel-soil model; `surface` and `fit` fit polynomials.
  TerramechanicsOptions tm;
  auto* tm_cmd = cli.add_subcommand(
      "terramechanics", "Drawbar pull, resistive torque, sinkage and entry angle of a rigid wheel");
  // The parent command's options are checked in run_terramechanics, so that
  // `terramechanics fit FILE` does not ask for them.
  auto add_model_options = [](CLI::App* cmd, TerramechanicsOptions& o, bool need_lists) {
    auto* soil = cmd->add_option("--soil", o.soil, "Soil NAME (resources/soils/NAME.json) or FILE");
    auto* radius = cmd->add_option("--radius", o.radius, "Wheel radius, m");
    auto* width = cmd->add_option("--width", o.width, "Wheel width, m");
    if (!need_lists) {
      soil->required();
      radius->required();
      width->required();
    }
    cmd->add_option("--grousers", o.grousers, "Number of grousers");
    cmd->add_option("--grouser-height", o.grouser_height, "Grouser height, m");
    if (need_lists) {
      cmd->add_option("--load", o.loads, "Normal loads W, N (comma separated)")->delimiter(',');
      cmd->add_option("--slip", o.slips, "Slips s in [-1, 1] (comma separated)")->delimiter(',');
      cmd->add_option("--format", o.format, "csv or json")->capture_default_str();
    }
    cmd->add_option("--model", o.model,
                    "bekker | wong, with +slip-sinkage, +grousers, +bulldozing (e.g. wong+slip-sinkage)")
        ->capture_default_str();
    cmd->add_option("--integration", o.integration, "simpson | riemann")->capture_default_str();
    cmd->add_option("--riemann-points", o.riemann_points, "Points of the Riemann sum")->capture_default_str();
    cmd->add_option("--slip-sinkage-n1", o.slip_sinkage_n1, "n = n0 + n1 |s| (with +slip-sinkage)")->capture_default_str();
    cmd->add_option("--grouser-effectiveness", o.grouser_effectiveness, "shear radius r + lambda h (with +grousers)")
        ->capture_default_str();
    cmd->add_option("--bulldozing-scale", o.bulldozing_scale, "scale of the bulldozing resistance (with +bulldozing)")
        ->capture_default_str();
    cmd->add_option("--soil-strength", o.soil_strength, "factor on c, tan(phi), kc, kphi")->capture_default_str();
  };
  SurfaceOptions surface;
  auto* surface_cmd = tm_cmd->add_subcommand(
      "surface", "Fit DP(W, s) and tau_R(W, s) polynomials (Eq. 2.28) to a model grid, as in seed 003 Appendix A");
  add_model_options(surface_cmd, surface.model, false);
  surface_cmd->add_option("--load-min", surface.load_min, "N")->capture_default_str();
  surface_cmd->add_option("--load-max", surface.load_max, "N")->capture_default_str();
  surface_cmd->add_option("--slip-min", surface.slip_min)->capture_default_str();
  surface_cmd->add_option("--slip-max", surface.slip_max)->capture_default_str();
  surface_cmd->add_option("--grid", surface.grid, "Grid points per axis")->capture_default_str();
  surface_cmd->add_option("--order", surface.order, "Polynomial order 1..6, or auto (cross-validated)")->capture_default_str();
  surface_cmd->add_flag("--json", surface.json, "Print JSON");
  FitOptions fit;
  auto* fit_cmd = tm_cmd->add_subcommand(
      "fit", "Fit traction-surface polynomials to a CSV of points (load_N, slip, drawbar_pull_N / resistive_torque_Nm)");
  fit_cmd->add_option("FILE", fit.file, "CSV of points")->required();
  fit_cmd->add_option("--order", fit.order, "Polynomial order 1..6, or auto (cross-validated)")->capture_default_str();
  fit_cmd->add_option("--grid", fit.grid_bins, "Occupancy grid bins per axis")->capture_default_str();
  fit_cmd->add_flag("--json", fit.json, "Print JSON");
  add_model_options(tm_cmd, tm, true);
  tm_cmd->require_subcommand(0, 1);

  auto* discrepancy_cmd = cli.add_subcommand(
      "discrepancy", "Where a model disagrees with measured data, why, and what an extended model gains");
  discrepancy_cmd->require_subcommand(1);
  SingleWheelDiscrepancyOptions sw;
  auto* sw_cmd = discrepancy_cmd->add_subcommand(
      "single-wheel", "Baseline Wong-Reece against measured single-wheel points: residuals, cause, gain");
  sw_cmd->add_option("FILE", sw.file, "CSV: radius_m, width_m, load_N, slip and drawbar_pull_N / torque_Nm / sinkage_m")
      ->required();
  sw_cmd->add_option("--soil", sw.soil, "Soil NAME (resources/soils/NAME.json) or FILE")->required();
  sw_cmd->add_option("--integration", sw.integration, "simpson | riemann")->capture_default_str();
  sw_cmd->add_flag("--json", sw.json, "Print JSON");

  auto* estimate_cmd = cli.add_subcommand("estimate", "Run an estimator over a log");
  estimate_cmd->require_subcommand(1);
  InsSlipCommandOptions ins;
  auto* ins_cmd = estimate_cmd->add_subcommand(
      "ins-slip", "Error-state INS with ZUPT/ZARU/NHC pseudo-measurements and slip detection (seed 002)");
  ins_cmd->add_option("LOG", ins.file, "Log with imu and wheels streams (gps or truth/slip for metrics)")->required();
  ins_cmd->add_option("--mapping,-m", ins.mapping, "Mapping NAME or FILE for .mat/HDF5 input (e.g. wvu_pathfinder)");
  ins_cmd->add_flag("--no-zupt", ins.no_zupt, "No zero-velocity updates");
  ins_cmd->add_flag("--no-zaru", ins.no_zaru, "No zero-angular-rate updates");
  ins_cmd->add_flag("--no-nhc", ins.no_nhc, "No non-holonomic constraints");
  ins_cmd->add_flag("--no-odometry-aiding", ins.no_odometry_aiding,
                    "No wheel forward-speed update in the localisation filter (pseudo-measurements only)");
  ins_cmd->add_flag("--no-smoother", ins.no_smoother,
                    "Forward filter only, as on board (default: RTS smoothing over the whole log)");
  ins_cmd->add_option("--odometry-sigma", ins.odometry_sigma, "Standard deviation of the wheel-speed update, m/s")
      ->capture_default_str();
  ins_cmd->add_option("--output,-o", ins.output, "Write the log with the estimate streams to OUT.h5");
  ins_cmd->add_flag("--json", ins.json, "Print JSON");

  auto* scenario_cmd = cli.add_subcommand("scenario", "Write a simulated log with truth streams");
  scenario_cmd->require_subcommand(1);
  SkidSteerScenarioOptions skid;
  auto* skid_cmd = scenario_cmd->add_subcommand(
      "skid-steer-slip", "Four-wheel skid-steer drive with slip episodes of every class, IMU, wheels, GPS (seed 002)");
  skid_cmd->add_option("--seed", skid.seed, "Noise seed")->capture_default_str();
  skid_cmd->add_option("--effect", skid.effects,
                       "Hidden effect NAME=VALUE: left-radius-scale, right-radius-scale, radius-scale, "
                       "turning-track-factor, wheel-time-offset (s), slip (0: firm ground)");
  skid_cmd->add_option("--output,-o", skid.output, "OUT.h5")->required();

  ContactAngleCommandOptions contact;
  auto* contact_cmd = estimate_cmd->add_subcommand(
      "contact-angle", "Contact angles, side slip, slip and velocity of a six-wheel DH rover with an EKF or UKF (seed 000)");
  contact_cmd->add_option("LOG", contact.file, "Log with imu, joints and wheels streams (truth/ streams for errors)")->required();
  contact_cmd->add_option("--mapping,-m", contact.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
  contact_cmd->add_option("--rover", contact.rover, "Rover NAME (resources/rovers) or FILE (default: the log's rover)");
  contact_cmd->add_option("--model", contact.model, "smooth | c | c+ss")->capture_default_str();
  contact_cmd->add_option("--filter", contact.filter, "ekf | ukf")->capture_default_str();
  contact_cmd->add_option("--angle-model", contact.angle_model, "random-walk | damped")->capture_default_str();
  contact_cmd->add_flag("--reset-cross-covariance", contact.reset_cross_covariance,
                        "Zero P's off-diagonal elements every step (the seed's workaround)");
  contact_cmd->add_option("--process-noise", contact.process_noise,
                          "seed: 1e-5 per step on attitude and velocity as seed 000 section 6.2 | imu: only the IMU's noise drives them")
      ->capture_default_str();
  contact_cmd->add_option("--velocity-variance", contact.velocity_variance, "Velocity process noise per step, m^2/s^2");
  contact_cmd->add_option("--attitude-variance", contact.attitude_variance, "Attitude process noise per step, rad^2");
  contact_cmd->add_option("--slip-variance", contact.slip_variance, "Slip process noise per step");
  contact_cmd->add_option("--angle-variance", contact.angle_variance, "Contact / side-slip angle process noise per step, rad^2");
  contact_cmd->add_option("--joint-rate-window", contact.joint_rate_window,
                          "Fuse joint rates with the slope of the joint angles over this window, s (0: measured rates, as the seed)")
      ->capture_default_str();
  contact_cmd->add_option("--output,-o", contact.output, "Write the log with the estimate streams to OUT.h5");
  contact_cmd->add_flag("--json", contact.json, "Print JSON");

  std::vector<CLI::App*> flying_cmds;
  std::vector<FlyingRoverOptions> flying(3);
  const char* flying_names[3] = {"fl-bogie-rotation", "rear-bogie-rotation", "bump-crossing"};
  const char* flying_help[3] = {
      "Flying ExoMars BB2, front-left bogie turning 0.06 rad/s for 10 s, 3 cm/s forward (seed 000 section 6.3)",
      "Flying ExoMars BB2, rear bogie turning 0.06 rad/s for 10 s, 3 cm/s forward (seed 000 section 6.4)",
      "Flying ExoMars BB2: bogie motion of the left wheels crossing an 8 cm bump, all wheels steering (RoverLab)"};
  for (int k = 0; k < 3; ++k) {
    flying[static_cast<std::size_t>(k)].scenario = flying_names[k];
    auto* c = scenario_cmd->add_subcommand(flying_names[k], flying_help[k]);
    c->add_option("--seed", flying[static_cast<std::size_t>(k)].seed, "Noise seed")->capture_default_str();
    c->add_option("--rate", flying[static_cast<std::size_t>(k)].rate, "Sample rate, Hz")->capture_default_str();
    c->add_option("--rover", flying[static_cast<std::size_t>(k)].rover, "Rover NAME or FILE")->capture_default_str();
    c->add_option("--output,-o", flying[static_cast<std::size_t>(k)].output, "OUT.h5")->required();
    flying_cmds.push_back(c);
  }

  OdometryDiscrepancyOptions odo;
  auto* odo_cmd = discrepancy_cmd->add_subcommand(
      "odometry", "Wheel-odometry dead reckoning against the GPS track: cause of the disagreement, fitted correction, gain");
  odo_cmd->add_option("LOG", odo.file, "Log with wheels and gps streams")->required();
  odo_cmd->add_option("--mapping,-m", odo.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
  odo_cmd->add_option("--fit-fraction", odo.fit_fraction, "Share of the drive (by distance) used to fit; the rest tests")
      ->capture_default_str()->check(CLI::Range(0.1, 0.9));
  odo_cmd->add_flag("--json", odo.json, "Print JSON");

  RenderOptions render;
  auto* render_cmd = cli.add_subcommand(
      "render", "Render one view of a log to PNG, headless (starts a private Xvfb when DISPLAY is unset)");
  render_cmd->add_option("FILE", render.file, "Log (HDF5, .mat with --mapping, CSV) or single-wheel CSV")->required();
  render_cmd->add_option("--mapping,-m", render.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
  render_cmd->add_option("--view", render.view, "rover | traction-surface | contact-angles | timeseries")
      ->capture_default_str();
  render_cmd->add_option("--time,-t", render.time, "Time shown, s (default: mid-log)");
  render_cmd->add_option("--channels", render.channels, "timeseries: stream:channel,... (a stream alone: all its channels)");
  render_cmd->add_option("--soil", render.soil, "traction-surface: draw the Wong-Reece model surface of soil NAME|FILE");
  render_cmd->add_option("--quantity", render.quantity, "traction-surface: drawbar-pull | torque")->capture_default_str();
  render_cmd->add_option("--size", render.size, "WxH pixels")->capture_default_str();
  render_cmd->add_option("--output,-o", render.output, "OUT.png")->required();

  ReportOptions report;
  auto* report_cmd = cli.add_subcommand(
      "report", "Write an HTML report (views as PNG, metric tables, CSV and JSON) for a log into a folder");
  report_cmd->add_option("FILE", report.file, "Log (HDF5, .mat with --mapping, CSV) or single-wheel CSV")->required();
  report_cmd->add_option("--mapping,-m", report.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
  report_cmd->add_option("--soil", report.soil, "Add the traction surfaces of soil NAME|FILE");
  report_cmd->add_option("--size", report.size, "WxH pixels of the 3D views")->capture_default_str();
  report_cmd->add_option("--output,-o", report.output, "Report folder (created if missing)")->required();

  SimulateOptions sim;
  auto* simulate_cmd = cli.add_subcommand(
      "simulate", "Planar rocker-bogie dynamics with terramechanics (seed 003 chapter 4): a scenario to a log with truth");
  simulate_cmd->add_option("SCENARIO", sim.scenario, "Scenario NAME (resources/scenarios) or FILE.json")->required();
  simulate_cmd->add_option("--seed", sim.seed, "Sensor-noise seed")->capture_default_str();
  simulate_cmd->add_option("--effect", sim.effects,
                           "Effect NAME=VALUE: soil-strength, slip-sinkage, grousers, wheel-radius-scale, effect-start-x, "
                           "gyro-bias, accel-bias, force-offset, force-scale, encoder-dropout, imu-time-offset");
  simulate_cmd->add_option("--traction", sim.traction, "polynomial | wong-reece (default: the scenario's)");
  simulate_cmd->add_option("--duration", sim.duration, "s (default: the scenario's)");
  simulate_cmd->add_option("--output,-o", sim.output, "OUT.h5")->required();

  GuiOptions gui;
  auto* gui_cmd = cli.add_subcommand("gui", "The desktop application (Qt + VTK)");
  gui_cmd->add_option("FILE", gui.file, "Log to open");
  gui_cmd->add_option("--mapping,-m", gui.mapping, "Mapping NAME or FILE for .mat/HDF5 input (default: try the known ones)");
  gui_cmd->add_option("--screenshot", gui.screenshot, "Save the window as PNG once FILE is loaded and analysed, then exit");
  gui_cmd->add_option("--time,-t", gui.time, "With --screenshot: the timeline's time, s");
  gui_cmd->add_option("--tab", gui.tab, "With --screenshot: Rover | Plots | Traction surface | Analysis");
  gui_cmd->add_option("--width", gui.width, "Window width")->capture_default_str();
  gui_cmd->add_option("--height", gui.height, "Window height")->capture_default_str();

  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    cli.exit(e);
    return kUsageError;
  }
  if (info_cmd->parsed()) return run_info(info);
  if (convert_cmd->parsed()) return run_convert(convert);
  if (mappings_cmd->parsed()) return run_list_mappings();
  if (surface_cmd->parsed()) return run_terramechanics_surface(surface);
  if (fit_cmd->parsed()) return run_terramechanics_fit(fit);
  if (tm_cmd->parsed()) return run_terramechanics(tm);
  if (sw_cmd->parsed()) return run_discrepancy_single_wheel(sw);
  if (odo_cmd->parsed()) return run_discrepancy_odometry(odo);
  if (ins_cmd->parsed()) return run_estimate_ins_slip(ins);
  if (contact_cmd->parsed()) return run_estimate_contact_angle(contact);
  for (std::size_t k = 0; k < flying_cmds.size(); ++k) {
    if (flying_cmds[k]->parsed()) return run_scenario_flying_rover(flying[k]);
  }
  if (skid_cmd->parsed()) return run_scenario_skid_steer(skid);
  if (render_cmd->parsed()) return run_render(render);
  if (report_cmd->parsed()) return run_report(report);
  if (gui_cmd->parsed()) return run_gui(gui);
  if (simulate_cmd->parsed()) return run_simulate_rocker_bogie(sim);
  return kUsageError;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const roverlab::app::UsageError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kUsageError;
  } catch (const roverlab::InputError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kBadInput;
  } catch (const roverlab::DataError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kBadInput;
  } catch (const roverlab::views::EnvironmentError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kInternalFailure;
  } catch (const std::exception& e) {
    std::cerr << "roverlab: internal error: " << e.what() << "\n";
    return roverlab::app::kInternalFailure;
  } catch (...) {
    std::cerr << "roverlab: internal error\n";
    return roverlab::app::kInternalFailure;
  }
}
