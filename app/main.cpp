// roverlab: command-line entry point. Exit codes: 0 success, 2 usage error,
// 3 bad input, 4 internal failure.
#include <CLI/CLI.hpp>
#include <iostream>

#include "app/commands.h"
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

  auto* mappings_cmd = cli.add_subcommand("mappings", "List the importer mappings RoverLab knows");

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
  return kUsageError;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const roverlab::InputError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kBadInput;
  } catch (const roverlab::DataError& e) {
    std::cerr << "roverlab: " << e.what() << "\n";
    return roverlab::app::kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "roverlab: internal error: " << e.what() << "\n";
    return roverlab::app::kInternalFailure;
  } catch (...) {
    std::cerr << "roverlab: internal error\n";
    return roverlab::app::kInternalFailure;
  }
}
