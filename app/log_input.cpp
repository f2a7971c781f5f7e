#include "app/log_input.h"

#include "app/resources.h"
#include "importers/mapping.h"

namespace roverlab::app {

io::LoadedLog load_input(const std::string& file, const std::optional<std::string>& mapping) {
  io::LoadOptions options;
  if (mapping) {
    options.mapping = io::load_mapping(io::find_mapping(*mapping, resource_subfolders("mappings")));
  }
  return io::load_log(file, options);
}

}  // namespace roverlab::app
