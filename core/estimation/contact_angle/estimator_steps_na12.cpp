// ContactAngleEstimator's fixed-size steps with 12 angle states (estimator_steps.h).
#include "core/estimation/contact_angle/estimator_steps.h"

namespace roverlab::estimation {

template void ContactAngleEstimator::fast_ekf_step<12>(FastEkf<12>& fe, std::size_t i, const contact::Inputs& in,
                                                       double ts, bool update);
template void ContactAngleEstimator::fixed_ukf_step<12>(ContactAngleUkf<12>& u, std::size_t i,
                                                        const contact::Inputs& in, double ts, bool update);

}  // namespace roverlab::estimation
