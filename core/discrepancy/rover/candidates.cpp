#include "core/discrepancy/rover/candidates.h"

#include <utility>

namespace roverlab::analysis {

#define ROVERLAB_ROVER_CANDIDATE(x) std::unique_ptr<RoverCandidate> make_##x##_rover_candidate();
#include "core/discrepancy/rover/candidates.def"
#undef ROVERLAB_ROVER_CANDIDATE

namespace {

class FixedCandidate final : public RoverCandidate {
 public:
  FixedCandidate(const char* name, const char* cause, bool physical, std::vector<RoverCandidateParameter> p)
      : name_(name), cause_(cause), physical_(physical), parameters_(std::move(p)) {}
  const char* name() const override { return name_; }
  const char* cause() const override { return cause_; }
  bool physical() const override { return physical_; }
  std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures&) const override { return parameters_; }

 private:
  const char* name_;
  const char* cause_;
  bool physical_;
  std::vector<RoverCandidateParameter> parameters_;
};

}  // namespace

std::unique_ptr<RoverCandidate> fixed_rover_candidate(const char* name, const char* cause, bool physical,
                                                      std::vector<RoverCandidateParameter> parameters) {
  return std::make_unique<FixedCandidate>(name, cause, physical, std::move(parameters));
}

std::vector<std::unique_ptr<RoverCandidate>> rover_candidates() {
  std::vector<std::unique_ptr<RoverCandidate>> out;
#define ROVERLAB_ROVER_CANDIDATE(x) out.push_back(make_##x##_rover_candidate());
#include "core/discrepancy/rover/candidates.def"
#undef ROVERLAB_ROVER_CANDIDATE
  return out;
}

}  // namespace roverlab::analysis
