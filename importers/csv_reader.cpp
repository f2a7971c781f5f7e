// CSV logs (importers/csv_log.h) as a LogReader.
#include "importers/csv_log.h"
#include "importers/log_reader.h"

namespace roverlab::io {

namespace {

class CsvReader final : public LogReader {
 public:
  std::string name() const override { return "CSV"; }

  Confidence can_read(const std::string& path, const LoadOptions&) const override {
    return has_extension(path, {".csv", ".CSV", ".txt"}) ? Confidence::extension : Confidence::none;
  }

  log::Log read(const std::string& path, const LoadOptions&) const override { return read_csv_log(path); }
};

}  // namespace

std::unique_ptr<LogReader> make_csv_log_reader() { return std::make_unique<CsvReader>(); }

}  // namespace roverlab::io
