#pragma once
// The roverlab subcommands. Each returns the process exit code; errors are
// thrown (InputError -> 3, anything else -> 4) and reported by main.

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace roverlab::app {

enum ExitCode : int { kSuccess = 0, kUsageError = 2, kBadInput = 3, kInternalFailure = 4 };

// Options that parse but make no sense together (exit code 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Applies `--effect NAME=VALUE` options through `set` (which throws
// DataError for an unknown name or value); malformed options and rejected
// effects are UsageErrors.
void apply_effect_options(const std::vector<std::string>& options,
                          const std::function<void(const std::string& name, double value)>& set);

struct InfoOptions {
  std::string file;
  std::optional<std::string> mapping;
  bool json = false;
};
int run_info(const InfoOptions& options);

struct ConvertOptions {
  std::string input;
  std::string output;
  std::optional<std::string> mapping;
  std::optional<std::string> stream;  // the one stream a CSV output takes
};
int run_convert(const ConvertOptions& options);

int run_list_mappings();

}  // namespace roverlab::app

namespace roverlab::app {

struct TerramechanicsOptions {
  std::string soil;
  double radius = 0.0, width = 0.0;
  int grousers = 0;
  double grouser_height = 0.0;
  std::vector<double> loads, slips;
  std::string model = "wong";
  std::string integration = "simpson";
  int riemann_points = 500;
  double slip_sinkage_n1 = 0.3;
  double grouser_effectiveness = 1.0;
  double bulldozing_scale = 1.0;
  double soil_strength = 1.0;
  std::string format = "csv";
};
int run_terramechanics(const TerramechanicsOptions& options);

struct SurfaceOptions {
  TerramechanicsOptions model;
  double load_min = 0.1, load_max = 200.0, slip_min = 0.0, slip_max = 1.0;
  int grid = 100;
  std::string order = "4";  // 1..6 or auto
  bool json = false;
};
int run_terramechanics_surface(const SurfaceOptions& options);

struct FitOptions {
  std::string file;
  std::string order = "auto";
  int grid_bins = 10;
  bool json = false;
};
int run_terramechanics_fit(const FitOptions& options);

struct SingleWheelDiscrepancyOptions {
  std::string file;
  std::string soil;
  std::string integration = "simpson";
  bool json = false;
};
int run_discrepancy_single_wheel(const SingleWheelDiscrepancyOptions& options);

struct InsSlipCommandOptions {
  std::string file;
  std::optional<std::string> mapping;
  bool no_zupt = false, no_zaru = false, no_nhc = false;
  bool no_odometry_aiding = false;  // no wheel forward-speed update in the localisation filter
  bool no_smoother = false;         // forward filter only (what the rover had on board)
  double odometry_sigma = 0.05;  // m/s
  std::optional<std::string> output;
  bool json = false;
};
int run_estimate_ins_slip(const InsSlipCommandOptions& options);

struct SkidSteerScenarioOptions {
  unsigned seed = 1;
  std::vector<std::string> effects;  // NAME=VALUE
  std::string output;
};
int run_scenario_skid_steer(const SkidSteerScenarioOptions& options);

struct OdometryDiscrepancyOptions {
  std::string file;
  std::optional<std::string> mapping;
  double fit_fraction = 0.5;
  bool json = false;
};
int run_discrepancy_odometry(const OdometryDiscrepancyOptions& options);

struct RenderOptions {
  std::string file;
  std::optional<std::string> mapping;
  std::string view = "rover";
  std::optional<double> time;
  std::optional<std::string> channels;
  std::optional<std::string> soil;
  std::string quantity = "drawbar-pull";
  std::string size = "1280x800";
  std::string output;
};
int run_render(const RenderOptions& options);

struct ReportOptions {
  std::string file;
  std::optional<std::string> mapping;
  std::optional<std::string> soil;
  std::string quantity = "drawbar-pull";
  std::string size = "1280x800";
  std::string output;
};
int run_report(const ReportOptions& options);

struct GuiOptions {
  std::optional<std::string> file;
  std::optional<std::string> mapping;
  std::optional<std::string> screenshot;  // save the window as PNG and exit
  std::optional<double> time;
  std::optional<std::string> tab;  // Rover, Plots, Traction surface, Analysis
  int width = 1400, height = 900;
};
int run_gui(const GuiOptions& options);

struct FlyingRoverOptions {
  std::string scenario;
  std::string rover = "exomars_bb2";
  unsigned seed = 1;
  double rate = 1000.0;
  std::string output;
};
int run_scenario_flying_rover(const FlyingRoverOptions& options);

struct ContactAngleCommandOptions {
  std::string file;
  std::optional<std::string> mapping;
  std::optional<std::string> rover;  // default: the log's rover id, else exomars_bb2
  std::string model = "c", filter = "ekf", angle_model = "random-walk";
  bool reset_cross_covariance = false;
  std::string process_noise = "seed";  // seed (1e-5 per step, section 6.2) | imu (from the IMU noise alone)
  std::optional<double> velocity_variance, attitude_variance, slip_variance, angle_variance;
  double joint_rate_window = 0.0;
  std::optional<std::string> output;
  bool json = false;
};
int run_estimate_contact_angle(const ContactAngleCommandOptions& options);

struct SimulateOptions {
  std::string scenario;  // NAME (resources/scenarios) or FILE
  unsigned seed = 1;
  std::vector<std::string> effects;  // NAME=VALUE
  std::optional<std::string> traction;
  std::optional<double> duration;
  std::string output;
};
int run_simulate_rocker_bogie(const SimulateOptions& options);

}  // namespace roverlab::app
