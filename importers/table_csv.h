#pragma once
// A numeric CSV table with a header row of column names (an optional
// "[unit]" suffix is dropped): e.g. the output of `roverlab terramechanics`.

#include <string>
#include <vector>

namespace roverlab::io {

struct NumericTable {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;  // NaN for empty or non-numeric status cells
  const std::vector<double>* find(const std::string& name) const;
};

// Throws InputError naming the file and line: ragged row, unparsable number
// in a column listed in `numeric` or, when the file has it, in `numeric_if_present`
// (other columns may hold text); a column of `numeric` missing.
NumericTable read_numeric_table(const std::string& path, const std::vector<std::string>& numeric,
                                const std::vector<std::string>& numeric_if_present = {});

}  // namespace roverlab::io
