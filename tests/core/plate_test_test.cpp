#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "core/common/error.h"
#include "core/terramechanics/plate_test.h"
#include "core/terramechanics/rft.h"

using namespace roverlab::terramechanics;

namespace {

using Pressure = std::function<double(double b, double z)>;

// A simulated plate test: the plate starts 1 cm above the soil, sinks to 5 cm,
// rises to 3 cm (a linear elastic rebound, as Wong 2008 Ch. 2 describes unloading: p = p_u - k_u (z_u - z)),
// sinks again to 7 cm (reloading along the rebound line, then the virgin
// curve) and leaves the soil. Depth exact (arm encoders), force noise sigma N.
PlateRecord simulate(const Plate& plate, const Pressure& p, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  PlateRecord r;
  r.name = "simulated";
  r.plate = plate;
  std::vector<double> path;
  const auto go = [&](double from, double to) {
    const int steps = static_cast<int>(std::round(std::abs(to - from) / 2e-4));
    for (int i = 0; i < steps; ++i) path.push_back(from + (to - from) * i / steps);
  };
  go(-0.01, 0.05);
  go(0.05, 0.03);
  go(0.03, 0.07);
  go(0.07, -0.005);
  double deepest = 0.0;
  for (double z : path) {
    double pressure = 0.0;
    if (z >= deepest) {
      deepest = z;
      pressure = p(plate.b(), z);
    } else if (deepest > 0) {
      const double pu = p(plate.b(), deepest), ku = 20.0 * pu / deepest;
      pressure = std::max(0.0, pu - ku * (deepest - z));
    }
    r.depth.push_back(z);
    r.force.push_back(plate.area() * pressure + sigma * unit(rng));
  }
  return r;
}

Plate circle(double diameter) { return Plate{true, diameter, diameter}; }

struct Coverage {
  int within = 0, total = 0;
  void add(double estimate, double sigma, double truth) {
    ++total;
    if (std::isfinite(sigma) && std::abs(estimate - truth) <= 2.0 * sigma) ++within;
  }
};

// 100 seeds at 95.4 % nominal coverage: 88..100 holds 99.8 % of the binomial.
void expect_calibrated(const Coverage& c, const char* what) {
  std::printf("%s: %d/%d within 2 sigma\n", what, c.within, c.total);
  EXPECT_GE(c.within, 88 * c.total / 100) << what;
}

constexpr int kSeeds = 100;

}  // namespace

TEST(PlateTest, RftPlateCoefficientIsLisGenericIntrusionValue) {
  // Table S2 of Li et al. (2013): a horizontal plate moving down feels the sum
  // of A00, A10, B01, B11, B-11; moving up, A00 + A10 - B01 - B11 - B-11.
  // The plate's coefficient is the RFT wheel model's own (rft.h), not a copy.
  EXPECT_NEAR(generic_alpha(0.0, M_PI / 2).z, 1.000, 1e-12);
  EXPECT_NEAR(generic_alpha(0.0, -M_PI / 2).z, -0.250, 1e-12);
  EXPECT_NEAR(rft_pressure(0.3, 0.02), 0.3 * 1e6 * 0.02, 1e-6);
}

TEST(PlateTest, TellsApproachLoadingUnloadingAndReloadingApartAndFindsContact) {
  const Pressure bekker = [](double b, double z) { return bekker_pressure(15600, 2.4e6, 1.1, b, z); };
  const PlateRecord r = simulate(circle(0.1), bekker, 2.0, 1);
  const PlateSegmentation s = segment_plate_record(r);
  std::vector<PlateSegmentKind> kinds;
  for (const auto& seg : s.segments) kinds.push_back(seg.kind);
  const std::vector<PlateSegmentKind> expected{PlateSegmentKind::approach,  PlateSegmentKind::loading,
                                               PlateSegmentKind::unloading, PlateSegmentKind::reloading,
                                               PlateSegmentKind::loading,   PlateSegmentKind::unloading};
  ASSERT_EQ(kinds.size(), expected.size());
  EXPECT_EQ(kinds, expected);
  // Contact (depth 0) is sample 50; the threshold crossing comes a few samples later.
  EXPECT_GE(s.contact, 50U);
  EXPECT_LE(s.contact, 60U);
  EXPECT_NEAR(s.force_noise, 2.0, 0.4);
  // Virgin samples: 0 .. 5 cm and 5 .. 7 cm, never the rebound or its reloading.
  for (std::size_t i : s.virgin) {
    const bool first = r.depth[i] <= 0.05 + 1e-12 && i<400, second = r.depth[i]> 0.05 && i >= 400;
    EXPECT_TRUE(first || second) << i;
  }
}

TEST(PlateTest, BekkerTruthWithTwoPlateSizesIsFittedWithinTwoSigma) {
  const double kc = 15600, kphi = 2.4e6, n = 1.1;
  const Pressure truth = [&](double b, double z) { return bekker_pressure(kc, kphi, n, b, z); };
  Coverage ckc, ckphi, cn;
  PlateFitOptions o;
  o.folds = 0;  // no held-out refits: coverage only (HeldOutError... below)
  for (int seed = 0; seed < kSeeds; ++seed) {
    const auto a = analyse_plate_tests(
        {simulate(circle(0.1), truth, 5.0, 2 * seed + 100), simulate(circle(0.2), truth, 5.0, 2 * seed + 101)}, o);
    ASSERT_EQ(a.plate_sizes.size(), 2U);
    const PressureSinkageFit& f = a.fits[0];
    ASSERT_TRUE(f.sizes_separated);
    ASSERT_TRUE(f.covariance_ok);
    ckc.add(f.find("kc")->value, f.find("kc")->sigma, kc);
    ckphi.add(f.find("kphi")->value, f.find("kphi")->sigma, kphi);
    cn.add(f.find("n")->value, f.find("n")->sigma, n);
    EXPECT_NEAR(f.contact_depths[0], 0.0, 1e-3);
  }
  expect_calibrated(ckc, "bekker kc");
  expect_calibrated(ckphi, "bekker kphi");
  expect_calibrated(cn, "bekker n");
}

// Held out, the true family predicts to the noise; RFT (linear in depth, the
// same for both sizes) cannot follow a Bekker soil with n = 1.1 and k_c > 0.
TEST(PlateTest, HeldOutErrorOfTheTrueFamilyIsTheNoiseAndAWrongFamilysIsMore) {
  const Pressure truth = [](double b, double z) { return bekker_pressure(15600, 2.4e6, 1.1, b, z); };
  for (int seed = 0; seed < 5; ++seed) {
    const auto a = analyse_plate_tests(
        {simulate(circle(0.1), truth, 5.0, 2 * seed + 300), simulate(circle(0.2), truth, 5.0, 2 * seed + 301)}, {});
    EXPECT_LT(a.fits[0].held_out_rmse_N, 1.5 * 5.0);
    EXPECT_GT(a.fits[2].held_out_rmse_N, 3.0 * a.fits[0].held_out_rmse_N);
    std::printf("held-out rmse: bekker %.2f N, reece %.2f N, rft %.2f N (noise 5 N)\n", a.fits[0].held_out_rmse_N,
                a.fits[1].held_out_rmse_N, a.fits[2].held_out_rmse_N);
  }
}

TEST(PlateTest, ReeceTruthWithTwoPlateSizesIsFittedWithinTwoSigma) {
  const double k1 = 1e4, k2 = 8e5, n = 1.0;
  const Pressure truth = [&](double b, double z) { return reece_pressure(k1, k2, n, b, z); };
  Coverage c1, c2, cn;
  for (int seed = 0; seed < kSeeds; ++seed) {
    PlateFitOptions o;
    o.cohesion = 250.0;
    o.unit_weight = 15000.0;
    o.folds = 0;  // no held-out refits: coverage only
    const auto a = analyse_plate_tests(
        {simulate(circle(0.1), truth, 5.0, 2 * seed + 500), simulate(circle(0.2), truth, 5.0, 2 * seed + 501)}, o);
    const PressureSinkageFit& f = a.fits[1];
    ASSERT_TRUE(f.covariance_ok);
    c1.add(f.find("c_kc_prime")->value, f.find("c_kc_prime")->sigma, k1);
    c2.add(f.find("gamma_kphi_prime")->value, f.find("gamma_kphi_prime")->sigma, k2);
    cn.add(f.find("n")->value, f.find("n")->sigma, n);
    EXPECT_NEAR(f.find("kc_prime")->value, f.find("c_kc_prime")->value / 250.0, 1e-9);
  }
  expect_calibrated(c1, "reece c k'c");
  expect_calibrated(c2, "reece gamma k'phi");
  expect_calibrated(cn, "reece n");
}

TEST(PlateTest, RftTruthIsFittedWithinTwoSigma) {
  const double zeta = 0.3;
  const Pressure truth = [&](double, double z) { return rft_pressure(zeta, z); };
  Coverage cz;
  PlateFitOptions o;
  o.folds = 0;  // no held-out refits: coverage only
  for (int seed = 0; seed < kSeeds; ++seed) {
    const auto a = analyse_plate_tests(
        {simulate(circle(0.1), truth, 2.0, 2 * seed + 900), simulate(circle(0.2), truth, 2.0, 2 * seed + 901)}, o);
    const PressureSinkageFit& f = a.fits[2];
    ASSERT_TRUE(f.covariance_ok);
    cz.add(f.find("zeta")->value, f.find("zeta")->sigma, zeta);
    // A linear, size-free truth is a Bekker soil with k_c = 0, n = 1.
    EXPECT_NEAR(a.fits[0].find("n")->value, 1.0, 5.0 * a.fits[0].find("n")->sigma);
  }
  expect_calibrated(cz, "rft zeta");
}

TEST(PlateTest, OnePlateSizeFitsTheLumpedModulusAndSaysSo) {
  const Pressure truth = [](double b, double z) { return bekker_pressure(15600, 2.4e6, 1.1, b, z); };
  Coverage ck;
  PlateFitOptions o;
  o.folds = 0;  // no held-out refits: coverage only
  for (int seed = 0; seed < kSeeds; ++seed) {
    const auto a = analyse_plate_tests({simulate(circle(0.1), truth, 5.0, seed + 2000)}, o);
    const PressureSinkageFit& f = a.fits[0];
    EXPECT_FALSE(f.sizes_separated);
    EXPECT_EQ(f.find("kc"), nullptr);
    EXPECT_NE(f.note.find("one plate size"), std::string::npos);
    ck.add(f.find("k_eq")->value, f.find("k_eq")->sigma, 15600 / 0.05 + 2.4e6);
  }
  expect_calibrated(ck, "bekker k_eq, one size");
}

TEST(PlateTest, ARecordThatNeverTouchesIsADataErrorNamingIt) {
  PlateRecord r = simulate(
      circle(0.1), [](double, double) { return 0.0; }, 1.0, 3);
  r.name = "air.csv";
  try {
    segment_plate_record(r);
    FAIL() << "no error";
  } catch (const roverlab::DataError& e) {
    EXPECT_NE(std::string(e.what()).find("air.csv"), std::string::npos) << e.what();
  }
}

// The fitted curve a view draws (fitted_force) is the fit's own prediction:
// on the virgin loading samples it leaves residuals of the noise, the fit's RMSE.
TEST(PlateTest, FittedForceIsTheFitsPredictionOnItsSamples) {
  const Pressure truth = [](double b, double z) { return bekker_pressure(15600, 2.4e6, 1.1, b, z); };
  PlateFitOptions o;
  o.folds = 0;
  const std::vector<PlateRecord> records = {simulate(circle(0.1), truth, 5.0, 7), simulate(circle(0.2), truth, 5.0, 8)};
  const auto a = analyse_plate_tests(records, o);
  for (const PressureSinkageFit& f : a.fits) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t r = 0; r < records.size(); ++r) {
      for (std::size_t i : a.records[r].virgin) {
        const double e =
            records[r].force[i] - fitted_force(f, records[r].plate, f.contact_depths[r], records[r].depth[i]);
        sum += e * e;
        ++n;
      }
      EXPECT_EQ(fitted_force(f, records[r].plate, f.contact_depths[r], f.contact_depths[r] - 0.01),
                0.0);  // above the soil
    }
    ASSERT_EQ(n, f.samples) << to_string(f.model);
    EXPECT_NEAR(std::sqrt(sum / static_cast<double>(n)), f.rmse_N, 1e-6 * f.rmse_N + 1e-9) << to_string(f.model);
  }
  EXPECT_LT(a.fits[0].rmse_N, 6.0);  // Bekker: the noise (5 N)
}
