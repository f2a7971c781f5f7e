#pragma once
// The rover configuration in 3D from its DH description (seed 000 chapter 4):
// body, the links of every wheel's chain, and wheels of the rover's radius,
// posed at each time from the log's joint angles (body at the origin, levelled
// by the log's attitude when it has one). At each wheel's contact point: the
// direction of the wheel's velocity at the contact angle (estimate blue, truth
// green; seed 000 Fig. 5.1), the side-slip direction (orange), the estimate's
// 1-sigma as a fan when the log has it, and the wheel coloured by slip. The
// ground under each side follows the wheels' contact points (a bump shows).

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/kinematics/rover_model.h"
#include "core/log/log.h"
#include "views/view.h"

namespace roverlab::views {

// Empty when the scene can be drawn (a DH rover and a joints stream with its
// joints), else what is missing.
std::string articulated_rover_needs(const log::Log& log, const kinematics::RoverModel* rover);

class ArticulatedRoverScene : public Scene {
 public:
  ArticulatedRoverScene(const log::Log& log, kinematics::RoverModel rover);
  ~ArticulatedRoverScene() override;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  void set_time(double t) override;
  double start_time() const override { return t0_; }
  double end_time() const override { return t1_; }
  std::vector<std::string> notes() const override { return notes_; }
  // The text at the top: time, rover, model, and the key of what is drawn.
  std::string caption() const;
  // The wheel labels (FL .. FR) and where each is drawn.
  std::vector<std::pair<std::string, Eigen::Vector3d>> wheel_labels() const;

  // What set_time drew, in the body frame g (m): each wheel's centre and
  // contact point, and the contact-angle arrow's unit direction (estimate;
  // NaN when the log has none).
  const std::vector<Eigen::Vector3d>& wheel_centres() const { return centres_; }
  const std::vector<Eigen::Vector3d>& contact_points() const { return contacts_; }
  const std::vector<Eigen::Vector3d>& contact_directions() const { return directions_; }
  // The ground drawn under the wheels: each side's strip through its wheels'
  // contact points, tangent there at the contact angle (the truth's when the
  // log has it, else the estimate's, else level), so that every wheel touches
  // the ground where the kinematics put it and a bump shows as the strip's
  // rise; the points where each wheel meets it; each strip's vertices, in
  // pairs across it from the rear (body frame, m); the base plane's bounds,
  // below every strip.
  const std::vector<Eigen::Vector3d>& ground_contacts() const { return ground_contacts_; }
  std::vector<std::vector<Eigen::Vector3d>> ground_strips() const;
  std::vector<double> base_plane_bounds() const;

 private:
  struct Parts;
  void pose_wheel(std::size_t w, const std::vector<double>& q, std::size_t k_estimate, std::size_t k_truth);
  void place_ground();
  std::unique_ptr<Parts> parts_;
  kinematics::RoverModel rover_;
  double t0_ = 0, t1_ = 0;
  std::vector<std::string> notes_;
  std::vector<Eigen::Vector3d> centres_, contacts_, directions_, ground_contacts_, ground_tangents_;
};

}  // namespace roverlab::views
