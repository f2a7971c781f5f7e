#include "core/terramechanics/model_grid.h"

#include <stdexcept>

namespace roverlab::terramechanics {

SlipAngleTraction model_at(const GridModel& model, double load, double slip, std::optional<double> slip_angle) {
  if (slip_angle) {
    return evaluate_slip_angle(model.soil, model.wheel, load, slip, *slip_angle, model.options, model.lateral);
  }
  SlipAngleTraction out;
  static_cast<Traction&>(out) = evaluate(model.soil, model.wheel, load, slip, model.options);
  return out;
}

ModelCurve model_curve(const GridModel& model, double load, std::optional<double> slip_angle, double slip_min,
                       double slip_max, int points) {
  if (points < 2) throw std::invalid_argument("model_curve: at least 2 points");
  ModelCurve c;
  c.slip.reserve(static_cast<std::size_t>(points));
  c.traction.reserve(static_cast<std::size_t>(points));
  for (int k = 0; k < points; ++k) {
    const double slip = slip_min + (slip_max - slip_min) * k / (points - 1);
    c.slip.push_back(slip);
    c.traction.push_back(model_at(model, load, slip, slip_angle));
  }
  return c;
}

ModelGrid model_grid(const GridModel& model, const GridRange& r, std::optional<double> slip_angle,
                     const std::function<void(int, int)>& row_done) {
  if (r.loads < 2 || r.slips < 2) throw std::invalid_argument("model_grid: at least 2 nodes per axis");
  ModelGrid g;
  for (int i = 0; i < r.loads; ++i) {
    const double load = r.load_min + (r.load_max - r.load_min) * i / (r.loads - 1);
    for (int k = 0; k < r.slips; ++k) {
      const double slip = r.slip_min + (r.slip_max - r.slip_min) * k / (r.slips - 1);
      const SlipAngleTraction t = model_at(model, load, slip, slip_angle);
      if (!t.ok()) {
        ++g.unsupported;
        continue;
      }
      g.drawbar_pull.push_back({load, slip, t.drawbar_pull});
      g.resistive_torque.push_back({load, slip, t.resistive_torque});
      g.lateral_force.push_back({load, slip, t.lateral_force});
    }
    if (row_done) row_done(i, r.loads);
  }
  return g;
}

}  // namespace roverlab::terramechanics
