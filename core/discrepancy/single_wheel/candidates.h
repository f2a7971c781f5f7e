#pragma once
// The candidate causes of the single-wheel discrepancy study: each one a
// class with its name, its cause in plain words, the model extension it
// switches on and the parameters it frees. The list is
// single_wheel_candidates.def; adding a candidate is one file defining its
// factory plus one line there (docs/design.md).

#include <memory>
#include <utility>
#include <vector>

#include "core/terramechanics/soil_identification.h"

namespace roverlab::analysis {

class SingleWheelCandidate {
 public:
  virtual ~SingleWheelCandidate() = default;
  virtual const char* name() const = 0;
  virtual const char* cause() const = 0;
  // The parameters it fits with their start values (a negative start keeps
  // the soil's own value as the start).
  virtual std::vector<std::pair<terramechanics::Parameter, double>> parameters() const = 0;
  // Applies only when some wheel in the data has grousers.
  virtual bool needs_grousers() const { return false; }
  // Applies only when the data has points at a slip angle (the slip-angle model).
  virtual bool needs_lateral_force() const { return false; }
  // Switches on the model extension it stands for.
  virtual void configure(terramechanics::Extensions&) const {}
  // Whether it extends the model family `kind` (model.h): by default the
  // Wong-Reece / Ishigami family's extensions, not RFT's.
  virtual bool belongs_to(terramechanics::ModelKind kind) const { return kind != terramechanics::ModelKind::rft; }
};

// One candidate of each entry in single_wheel_candidates.def, in its order.
std::vector<std::unique_ptr<SingleWheelCandidate>> single_wheel_candidates();

}  // namespace roverlab::analysis
