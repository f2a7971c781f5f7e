#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/log/units.h"

using namespace roverlab::log;

TEST(Units, ConvertsToSI) {
  const auto deg = unit_to_si("deg");
  EXPECT_EQ(deg.si_unit, "rad");
  EXPECT_NEAR(180.0 * deg.factor, M_PI, 1e-15);
  EXPECT_EQ(unit_to_si("deg/s").si_unit, "rad/s");
  EXPECT_NEAR(unit_to_si("rpm").factor * 60.0, 2.0 * M_PI, 1e-12);
  EXPECT_NEAR(unit_to_si("g_n").factor, 9.80665, 1e-12);
  EXPECT_EQ(unit_to_si("mm").factor, 1e-3);
  EXPECT_EQ(unit_to_si("Nm").si_unit, "N*m");
  EXPECT_EQ(unit_to_si("N m").si_unit, "N*m");
  EXPECT_NEAR(unit_to_si("km/h").factor * 3.6, 1.0, 1e-15);
  const auto c = unit_to_si("degC");
  EXPECT_NEAR(20.0 * c.factor + c.offset, 293.15, 1e-12);
  // Every SI unit maps to itself with factor 1.
  for (const auto& name : known_units()) {
    const auto si = unit_to_si(name);
    const auto again = unit_to_si(si.si_unit);
    EXPECT_EQ(again.si_unit, si.si_unit) << name;
    EXPECT_EQ(again.factor, 1.0) << name;
    EXPECT_EQ(again.offset, 0.0) << name;
  }
}

TEST(Units, UnknownUnitIsAnErrorNamingIt) {
  EXPECT_FALSE(is_known_unit("furlong"));
  EXPECT_FALSE(is_known_unit("Deg"));
  try {
    unit_to_si("furlong");
    FAIL();
  } catch (const roverlab::DataError& e) {
    EXPECT_NE(std::string(e.what()).find("'furlong'"), std::string::npos);
  }
}
