#pragma once
// The contact-angle view (seed 000 Fig. 5.1): one panel per wheel, the wheel
// seen from the side with an arrow along its velocity in the wheel plane —
// the contact angle gamma, estimate in blue and truth in green when the log
// has both — and, seen from above, an arrow at the side-slip angle beta where
// it is estimated. Panels follow the timeline.

#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/log/log.h"
#include "views/view.h"

class vtkRenderer;

namespace roverlab::views {

// Empty when the log holds contact-angle estimates, else what it lacks.
std::string contact_angle_needs(const log::Log& log);

class ContactAngleScene : public Scene {
 public:
  // Reads estimate/contact/wheels (contact_angle_<w>, side_slip_<w>) and
  // truth/wheels. Throws DataError (contact_angle_needs) when the log has no
  // contact-angle estimate.
  explicit ContactAngleScene(const log::Log& log);
  ~ContactAngleScene() override;

  // One renderer per wheel, each with its viewport set (add them all to a window).
  const std::vector<vtkSmartPointer<vtkRenderer>>& renderers() const;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  // Call after attach: the panels fit the window's aspect.
  void set_time(double t) override;
  double start_time() const override { return t0_; }
  double end_time() const override { return t1_; }
  const std::vector<std::string>& wheels() const { return wheels_; }
  // Angles shown at the last set_time, rad (NaN when undefined).
  double shown_contact_angle(std::size_t wheel) const;
  static constexpr double estimate_rgb[3] = {0.12, 0.35, 0.85};
  static constexpr double truth_rgb[3] = {0.1, 0.6, 0.2};

 private:
  struct Parts;
  struct Panel;
  Panel make_panel(std::size_t wheel) const;
  void show_panel(std::size_t wheel, std::size_t k, std::size_t kr);
  std::unique_ptr<Parts> parts_;
  std::vector<std::string> wheels_;
  double t0_ = 0, t1_ = 0;
};

}  // namespace roverlab::views
