#pragma once
// Generic nonlinear Kalman filters over Eigen types (seed 000 section 2.5):
// an EKF with non-additive process and measurement noise (Eq. 2.14-2.17,
// Jacobians F, L, H, M supplied by the model, e.g. through ceres::Jet) and an
// augmented-state UKF (Eq. 2.18-2.20). Models stay outside the filters.

#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "core/filters/kalman.h"

namespace roverlab::estimation {

// A function's value and its Jacobians with respect to the state (dx) and
// the noise (dn) at the current estimate and zero noise.
struct Linearized {
  Eigen::VectorXd value;
  Eigen::MatrixXd dx, dn;
};

class ExtendedKalmanFilter {
 public:
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  // Eq. 2.14-2.15: x <- f(x, 0), P <- F P F^T + L Q L^T.
  void predict(const Linearized& f, const Eigen::MatrixXd& Q);
  // The same with uncorrelated noises: Q = diag(q), L Q L^T = (L sqrt(q)) (L sqrt(q))^T.
  void predict_diagonal(const Linearized& f, const Eigen::VectorXd& q);
  // Eq. 2.16-2.17 with the Joseph form: S = H P H^T + M R M^T.
  UpdateResult update(const Linearized& h, const Eigen::MatrixXd& R, const Eigen::VectorXd& y);
  // The same with uncorrelated measurement noises R = diag(r); an innovation
  // whose NIS exceeds `gate` is rejected (x and P left as they were).
  UpdateResult update_diagonal(const Linearized& h, const Eigen::VectorXd& r, const Eigen::VectorXd& y,
                               double gate = HUGE_VAL);
  // The seed's workaround: zero P's off-diagonal elements.
  void reset_cross_covariance();
};

class UnscentedKalmanFilter {
 public:
  // f(x, process noise, out) writes the next state; h(x, measurement noise,
  // out) the measurement (into preallocated vectors: no allocation per
  // sigma point).
  using Function = std::function<void(const Eigen::VectorXd&, const Eigen::VectorXd&, Eigen::VectorXd&)>;
  Eigen::VectorXd x;
  Eigen::MatrixXd P;
  double alpha = 1.0, beta = 2.0, kappa = 0.0;  // scaled unscented transform
  // The model's promise that the first nx process noises add to f's value
  // (x' = f(x, 0 + rest) + n) and the last ny measurement noises to h's.
  // Their sigma points then have closed forms: f is not evaluated along the
  // former, h not along the latter; the estimates are the same.
  bool additive_process_noise = false, additive_measurement_noise = false;
  // Optional: h at a sigma point that differs from the centre (X_0, 0) only
  // in the listed state and noise entries, given h(X_0, 0) = y0; must equal
  // h(x, n). Lets a model recompute only what those entries reach.
  using IncrementalFunction =
      std::function<void(const Eigen::VectorXd& x, const Eigen::VectorXd& n, const std::vector<Eigen::Index>& changed_x,
                         const std::vector<Eigen::Index>& changed_n, const Eigen::VectorXd& y0, Eigen::VectorXd& out)>;
  IncrementalFunction h_incremental;
  // The seed's workaround inside the step: P is diagonal on entry and only
  // the diagonal of the updated P is computed and kept.
  bool diagonal_only = false;
  // NIS gate of the update (a chi-square quantile); the last step's NIS
  // (y - ym)^T Pyy^-1 (y - ym) and whether the gate rejected it (the state
  // is then left as predicted).
  double gate = HUGE_VAL;
  double nis = 0;
  double log_det_pyy = 0;  // ln det Pyy of the last update (its innovation's likelihood)
  bool rejected = false;
  // One predict-update cycle on sigma points of the augmented state
  // [x; n_p; n_m] (Eq. 2.18-2.20). Returns false when a covariance is not
  // positive definite (the state is then left as predicted).
  //
  // The augmented covariance blockdiag(P, Q, R) is factorised block by block
  // (its Cholesky factor is block diagonal; Q's and R's are kept while they
  // do not change), and the sigma points along the measurement noises share
  // the centre's f(x, 0), which is evaluated once.
  bool step(const Function& f, const Eigen::MatrixXd& Q, const Function& h, const Eigen::MatrixXd& R,
            const Eigen::VectorXd& y);
  void reset_cross_covariance();

 private:
  // The steps of step(), in order; each reads what the previous ones left in
  // the members below.
  bool factor_covariances(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R, Eigen::Index ny);
  void propagate_sigma_points(const Function& f, Eigen::Index np);
  void measure_sigma_points(const Function& h, Eigen::Index nm, Eigen::Index ny);
  void measure_point(const Function& h, const Eigen::VectorXd& xp, const Eigen::VectorXd& noise,
                     Eigen::Ref<Eigen::VectorXd> out);
  void covariances(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);
  bool correct(const Eigen::VectorXd& y);

  Eigen::MatrixXd Q_, R_, SQ_, SR_;  // last noise covariances and their Cholesky factors
  Eigen::MatrixXd X_, Y_;            // sigma points through f and h
  // This step's sigma-point scale and weights, additive noise counts, the
  // state's scaled Cholesky factor, the points' measurement deviations (of
  // f's points, along the additive process noises, along the non-additive
  // measurement noises), the centre and the moments.
  Eigen::Index L_ = 0, pa_ = 0, ma_ = 0;
  double c_ = 0, wi_ = 0, wc0_ = 0;
  Eigen::MatrixXd Sx_, Yp_, Ym_, Dp_, Pxx_, Pyy_, Pxy_;
  Eigen::VectorXd X0_, Y0_, hy_, ym_;
  std::vector<Eigen::Index> changed_x_, changed_n_;
  // Scratch kept between steps (no allocation per step once sized): the
  // factorisations, f's arguments, the mean offsets, the innovation and gain
  // terms, and the dense columns of the outer products.
  Eigen::LLT<Eigen::MatrixXd> llt_x_, llt_y_;
  Eigen::VectorXd xs_, nps_, fx_, sx_, sy_, z_;
  Eigen::MatrixXd W_, D_, DB_;
  std::vector<Eigen::Index> dense_;
};

}  // namespace roverlab::estimation
