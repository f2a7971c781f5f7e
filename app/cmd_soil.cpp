// `roverlab soil plate FILE...`: soil parameters from plate-sinkage tests,
// written as a soil file that `--soil` of every command reads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "app/analysis.h"
#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/log_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/kinematics/arm.h"
#include "core/terramechanics/plate_test.h"
#include "importers/arm_file.h"
#include "importers/atomic_file.h"
#include "importers/plate_test_csv.h"
#include "importers/soil_file.h"

#ifndef ROVERLAB_VERSION
#define ROVERLAB_VERSION "unknown"
#endif

namespace roverlab::app {

struct PlateOptions {
  std::vector<std::string> files;
  std::string base = "dry_sand";
  std::string output;
  std::string samples;  // CSV of every record's samples with their segment
  std::string name;
  bool json = false;
  std::optional<std::string> mapping;
  std::string force, depth;  // STREAM/CHANNEL of a log
  std::string arm, joints = "joint_states";
  double diameter = 0, width = 0, length = 0;
  bool invert_force = false;
  bool invert_depth = false;
};

using nlohmann::json;
using namespace roverlab::terramechanics;

namespace {

// "STREAM/CHANNEL": the channel's time and values; InputError naming the file.
std::pair<std::vector<double>, std::vector<double>> channel_of(const log::Log& log, const std::string& spec,
                                                               const std::string& file, const char* option) {
  const auto slash = spec.rfind('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == spec.size()) {
    throw UsageError(std::string(option) + " '" + printable(spec) + "' is not STREAM/CHANNEL");
  }
  const log::Stream* s = log.find_stream(spec.substr(0, slash));
  if (s == nullptr)
    throw InputError(file, std::string(option) + ": no stream '" + printable(spec.substr(0, slash)) + "'");
  const log::Channel* c = s->find_channel(spec.substr(slash + 1));
  if (c == nullptr) {
    throw InputError(file, std::string(option) + ": stream " + s->name() + " has no channel '" +
                               printable(spec.substr(slash + 1)) + "'");
  }
  return {s->time(), c->values};
}

// Depth (m, positive down) from the arm's joint angles: the tool's height at
// the first sample minus its height at each.
std::pair<std::vector<double>, std::vector<double>> arm_depth(const log::Log& log, const PlateOptions& o,
                                                              const std::string& file) {
  const kinematics::ArmModel arm = io::find_arm(o.arm, resource_subfolders("arms"));
  const log::Stream* s = log.find_stream(o.joints);
  if (s == nullptr) throw InputError(file, "--joints: no stream '" + printable(o.joints) + "'");
  std::vector<const std::vector<double>*> angles;
  for (const auto& joint : arm.joints()) {
    const log::Channel* c = s->find_channel("position." + joint);
    if (c == nullptr) c = s->find_channel(joint);
    if (c == nullptr)
      throw InputError(file, "stream " + s->name() + " has no angle of joint " + joint + " (arm " + arm.name + ")");
    angles.push_back(&c->values);
  }
  std::vector<double> time, depth;
  std::vector<double> q(angles.size());
  double first = NAN;
  for (std::size_t i = 0; i < s->size(); ++i) {
    for (std::size_t j = 0; j < q.size(); ++j) q[j] = (*angles[j])[i];
    const double h = kinematics::arm_tool_height(arm, q);
    if (!std::isfinite(h)) continue;
    if (std::isnan(first)) first = h;
    time.push_back(s->time()[i]);
    depth.push_back(first - h);
  }
  return {time, depth};
}

// Linear interpolation of (t, v) at `at`; NaN outside its span.
double interpolate(const std::vector<double>& t, const std::vector<double>& v, double at) {
  if (t.empty() || at < t.front() || at > t.back()) return NAN;
  const auto it = std::lower_bound(t.begin(), t.end(), at);
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  if (i == 0 || t[i] == at) return v[i];
  const double w = (at - t[i - 1]) / (t[i] - t[i - 1]);
  return v[i - 1] + w * (v[i] - v[i - 1]);
}

Plate plate_of(const PlateOptions& o) {
  if (o.diameter > 0 && (o.width > 0 || o.length > 0)) {
    throw UsageError("give either --plate-diameter or --plate-width with --plate-length");
  }
  if (o.diameter > 0) return Plate{true, o.diameter, o.diameter};
  if (o.width > 0 && o.length > 0) return Plate{false, std::min(o.width, o.length), std::max(o.width, o.length)};
  throw UsageError("a log needs the plate's size: --plate-diameter D, or --plate-width W with --plate-length L (m)");
}

PlateRecord record_of_log(const std::string& file, const PlateOptions& o) {
  if (o.force.empty()) throw UsageError("a log needs --force STREAM/CHANNEL (and --depth STREAM/CHANNEL or --arm)");
  if (o.depth.empty() == o.arm.empty()) throw UsageError("give one of --depth STREAM/CHANNEL and --arm NAME|FILE");
  const Plate plate = plate_of(o);
  const io::LoadedLog loaded = load_input(file, o.mapping);
  const auto force = channel_of(loaded.log, o.force, file, "--force");
  const auto depth = o.arm.empty() ? channel_of(loaded.log, o.depth, file, "--depth") : arm_depth(loaded.log, o, file);
  PlateRecord r;
  r.name = file;
  r.plate = plate;
  for (std::size_t i = 0; i < force.first.size(); ++i) {
    const double z = interpolate(depth.first, depth.second, force.first[i]) * (o.invert_depth ? -1.0 : 1.0);
    const double f = force.second[i] * (o.invert_force ? -1.0 : 1.0);
    if (!std::isfinite(z) || !std::isfinite(f)) continue;
    r.depth.push_back(z);
    r.force.push_back(f);
  }
  return r;
}

PlateRecord read_record(const std::string& file, const PlateOptions& o) {
  const bool csv = std::filesystem::path(file).extension() == ".csv" && o.force.empty();
  return csv ? io::read_plate_test_csv(file) : record_of_log(file, o);
}

json parameter_json(const PlateParameter& p) {
  return {{"name", p.name},
          {"unit", p.unit},
          {"value", p.value},
          {"sigma", finite_or_null(p.sigma)},
          {"at_bound", p.at_bound}};
}

json analysis_json(const std::vector<PlateRecord>& records, const PlateAnalysis& a) {
  json files = json::array();
  for (std::size_t r = 0; r < records.size(); ++r) {
    const PlateSegmentation& s = a.records[r];
    json segments = json::array();
    for (const auto& seg : s.segments) {
      segments.push_back(
          {{"kind", to_string(seg.kind)}, {"first_sample", seg.begin}, {"samples", seg.end - seg.begin}});
    }
    const Plate& p = records[r].plate;
    files.push_back(
        {{"file", records[r].name},
         {"sha256", sha256_of_file(records[r].name)},
         {"plate", p.circular ? json{{"diameter_m", p.width}} : json{{"width_m", p.width}, {"length_m", p.length}}},
         {"b_m", p.b()},
         {"samples", records[r].depth.size()},
         {"force_noise_N", s.force_noise},
         {"contact_sample", s.contact},
         {"contact_seen", s.contact_seen},
         {"fitted_samples", s.virgin.size()},
         {"segments", segments}});
  }
  json fits = json::array();
  for (const auto& f : a.fits) {
    json params = json::array();
    for (const auto& p : f.parameters) params.push_back(parameter_json(p));
    fits.push_back({{"model", to_string(f.model)},
                    {"sizes_separated", f.sizes_separated},
                    {"parameters", params},
                    {"contact_depths_m", f.contact_depths},
                    {"samples", f.samples},
                    {"rmse_N", f.rmse_N},
                    {"held_out_rmse_N", f.held_out_rmse_N},
                    {"converged", f.converged},
                    {"covariance_ok", f.covariance_ok},
                    {"note", f.note}});
  }
  return {{"files", files}, {"plate_sizes_b_m", a.plate_sizes}, {"fits", fits}};
}

// The soil file: Bekker's n, k_c, k_phi from the plates; what plates do not
// measure (c, phi, K, c1, c2, density) from the base soil, and says so.
json soil_json(const PlateOptions& o, const Soil& base, const PlateAnalysis& a, const json& analysis) {
  const PressureSinkageFit& bekker = a.fits[0];
  const double n = bekker.find("n")->value;
  const double kc = bekker.sizes_separated ? bekker.find("kc")->value : 0.0;
  const double kphi = bekker.sizes_separated ? bekker.find("kphi")->value : bekker.find("k_eq")->value;
  std::string name = o.name.empty() ? std::filesystem::path(o.output).stem().string() : o.name;
  std::string invoked;
  for (const auto& arg : command_arguments()) invoked += (invoked.empty() ? "" : " ") + arg;
  return {{"format", "roverlab-soil"},
          {"version", 1},
          {"name", name},
          {"description",
           "From plate-sinkage tests (roverlab soil plate): n, kc, kphi fitted (Bekker); c, phi, K_s, "
           "c1, c2, density from the base soil " +
               base.name},
          {"source", "plate tests " + std::to_string(a.records.size()) +
                         " file(s) (plate_test.files); base soil: " + base.name + " (" + base.source + ")"},
          {"n", n},
          {"cohesion_Pa", base.cohesion},
          {"friction_angle_deg", base.friction_angle * 180.0 / M_PI},
          {"shear_modulus_m", base.shear_modulus},
          {"kc", kc},
          {"kc_unit", "Pa/m^(n-1)"},
          {"kphi", kphi},
          {"kphi_unit", "Pa/m^n"},
          {"c1", base.c1},
          {"c2", base.c2},
          {"density_kg_m3", base.density},
          {"plate_test",
           {{"roverlab_version", ROVERLAB_VERSION},
            {"command", invoked},
            {"analysis", analysis},
            {"kc_kphi_note", bekker.sizes_separated ? "" : bekker.note + "; written as kc = 0, kphi = k_eq"}}}};
}

void print_text(const std::vector<PlateRecord>& records, const PlateAnalysis& a) {
  for (std::size_t r = 0; r < records.size(); ++r) {
    const PlateSegmentation& s = a.records[r];
    std::printf(
        "%s: b = %.4g m, %zu samples, force noise %.3g N, contact at sample %zu%s; %zu loading samples fitted\n",
        printable(records[r].name).c_str(), records[r].plate.b(), records[r].depth.size(), s.force_noise, s.contact + 1,
        s.contact_seen ? "" : " (starts in contact)", s.virgin.size());
    for (const auto& seg : s.segments) {
      std::printf("  %-9s samples %zu-%zu, depth %.4g -> %.4g m\n", to_string(seg.kind), seg.begin + 1, seg.end,
                  records[r].depth[seg.begin], records[r].depth[seg.end - 1]);
    }
  }
  for (const auto& f : a.fits) {
    std::printf("%s: rmse %.3g N, held-out rmse %.3g N (%zu samples)%s; contact depth", to_string(f.model), f.rmse_N,
                f.held_out_rmse_N, f.samples, f.converged ? "" : ", not converged");
    for (double z0 : f.contact_depths) std::printf(" %.4g m", z0);
    std::printf("\n");
    for (const auto& p : f.parameters) {
      const std::string unit = p.unit == "1" ? "" : " " + p.unit;
      if (p.at_bound) {
        std::printf("  %-16s %.6g%s (at its bound)\n", p.name.c_str(), p.value, unit.c_str());
      } else {
        std::printf("  %-16s %.6g +- %.3g%s\n", p.name.c_str(), p.value, p.sigma, unit.c_str());
      }
    }
    if (!f.note.empty()) std::printf("  %s\n", f.note.c_str());
  }
}

// file, sample, depth_m, force_N, segment (approach, loading, ...) and whether it was fitted.
void write_samples(const std::string& path, const std::vector<PlateRecord>& records, const PlateAnalysis& a) {
  std::ostringstream out;
  out.precision(17);
  out << "record,sample,depth_m,force_N,segment,fitted\n";
  for (std::size_t r = 0; r < records.size(); ++r) {
    std::vector<const char*> kind(records[r].depth.size(), "approach");
    std::vector<int> fitted(records[r].depth.size(), 0);
    for (const auto& seg : a.records[r].segments) {
      for (std::size_t i = seg.begin; i < seg.end; ++i) kind[i] = to_string(seg.kind);
    }
    for (std::size_t i : a.records[r].virgin) fitted[i] = 1;
    for (std::size_t i = 0; i < records[r].depth.size(); ++i) {
      out << r + 1 << ',' << i + 1 << ',' << records[r].depth[i] << ',' << records[r].force[i] << ',' << kind[i] << ','
          << fitted[i] << '\n';
    }
  }
  io::write_text_atomically(path, out.str());
}

int run_plate(const PlateOptions& o) {
  for (const auto& f : o.files) {
    if (!o.output.empty()) refuse_overwriting_input(f, o.output, "-o");
    if (!o.samples.empty()) refuse_overwriting_input(f, o.samples, "--samples");
  }
  const Soil base = io::find_soil(o.base, resource_subfolders("soils"));
  std::vector<PlateRecord> records;
  for (const auto& f : o.files) records.push_back(read_record(f, o));
  PlateFitOptions fit;
  fit.cohesion = base.cohesion;
  fit.unit_weight = base.density * 9.80665;
  // A record's DataError names its file.
  const PlateAnalysis a = analyse_plate_tests(records, fit);
  const json analysis = analysis_json(records, a);
  if (o.json) {
    std::cout << analysis.dump(2) << "\n";
  } else {
    print_text(records, a);
  }
  if (!o.samples.empty()) write_samples(o.samples, records, a);
  if (o.output.empty()) return kSuccess;
  const json soil = soil_json(o, base, a, analysis);
  if (!(soil.at("kphi").get<double>() >= 0)) {
    throw DataError("the fitted kphi is negative: no soil file written (" + o.output + ")");
  }
  io::write_text_atomically(o.output, soil.dump(2) + "\n");
  io::load_soil(o.output);  // what --soil will read
  if (!o.json) std::printf("soil written to %s\n", printable(o.output).c_str());
  return kSuccess;
}

}  // namespace

Commands make_soil_commands() {
  Commands commands;
  commands.push_back(make_command<PlateOptions>(
      "soil plate",
      "Fit pressure-sinkage (Bekker, Reece, RFT) to plate-sinkage tests; write a soil file (-o) for --soil",
      [](CLI::App& cmd, PlateOptions& o) {
        cmd.add_option("FILE", o.files, "Plate tests: CSV (depth_m, force_N, '# plate_diameter_m: D') or logs")
            ->required();
        cmd.add_option("-o,--output", o.output, "Soil file to write (JSON)");
        cmd.add_option("--samples", o.samples, "CSV of the samples read (depth, force, segment, fitted)");
        cmd.add_option("--name", o.name, "Name of the soil (default: the output's stem)");
        cmd.add_option("--base", o.base, "Soil (NAME|FILE) giving what plates do not measure: c, phi, K_s, c1, c2")
            ->capture_default_str();
        cmd.add_option("-m,--mapping", o.mapping, "Importer mapping NAME|FILE for logs");
        cmd.add_option("--force", o.force, "Force channel of a log, STREAM/CHANNEL (N, positive pushing back)");
        cmd.add_option("--depth", o.depth, "Depth channel of a log, STREAM/CHANNEL (m, positive down)");
        cmd.add_option("--arm", o.arm, "Arm NAME|FILE (resources/arms): depth from its joint angles");
        cmd.add_option("--joints", o.joints, "Stream of the arm's joint angles")->capture_default_str();
        cmd.add_flag("--invert-force", o.invert_force, "The force channel is positive pulling (a wrench's z down)");
        cmd.add_flag("--invert-depth", o.invert_depth, "The --depth channel is a height (positive up)");
        cmd.add_option("--plate-diameter", o.diameter, "Circular plate of a log, m")->check(finite_in(1e-3, 10.0));
        cmd.add_option("--plate-width", o.width, "Rectangular plate of a log, m")->check(finite_in(1e-3, 10.0));
        cmd.add_option("--plate-length", o.length, "Rectangular plate of a log, m")->check(finite_in(1e-3, 10.0));
        cmd.add_flag("--json", o.json, "Print JSON");
      },
      run_plate));
  return commands;
}

}  // namespace roverlab::app
