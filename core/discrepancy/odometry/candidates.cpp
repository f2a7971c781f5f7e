#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

#define ROVERLAB_ODOMETRY_CANDIDATE(x) \
  std::unique_ptr<OdometryCandidateModel> make_##x##_odometry_candidate(const OdometryCandidateContext&);
#include "core/discrepancy/odometry/candidates.def"
#undef ROVERLAB_ODOMETRY_CANDIDATE

std::vector<OdometryParameter> OdometryCandidateModel::summary(const std::vector<double>& x,
                                                               const std::vector<double>& sigma) const {
  const std::vector<CandidateParameter> p = parameters();
  std::vector<OdometryParameter> out;
  for (std::size_t i = 0; i < p.size(); ++i) out.push_back({p[i].name, x[i], sigma[i]});
  return out;
}

std::vector<std::unique_ptr<OdometryCandidateModel>> odometry_candidates(const OdometryCandidateContext& context) {
  std::vector<std::unique_ptr<OdometryCandidateModel>> out;
#define ROVERLAB_ODOMETRY_CANDIDATE(x) out.push_back(make_##x##_odometry_candidate(context));
#include "core/discrepancy/odometry/candidates.def"
#undef ROVERLAB_ODOMETRY_CANDIDATE
  return out;
}

}  // namespace roverlab::analysis
