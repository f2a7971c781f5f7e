// ContactAngleEstimator's fixed-size steps with 12 angle states (steps.h).
#include "core/estimation/contact_angle/steps/steps.h"

ROVERLAB_CONTACT_ANGLE_STEPS(12);
