#include "hcpf/metrics/point_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hcpf/core/error.h"

namespace hcpf::metrics {
namespace {

constexpr double kPointTol = 1e-12;

TEST(Ospa, HandCheckedValues) {
  const std::vector<IdPoint> one = {{1, 0, 0}};
  const std::vector<IdPoint> two = {{1, 0, 0}, {2, 100, 0}};
  const std::vector<IdPoint> est = {{7, 3, 4}};
  // d = 5 < c = 10, equal cardinality: OSPA = (5^2 / 1)^(1/2) = 5.
  EXPECT_NEAR(Ospa(one, est, 10.0, 2.0), 5.0, kPointTol);
  // p = 1: (5 + 10 * (2 - 1)) / 2 = 7.5 (the far truth costs the cut-off).
  EXPECT_NEAR(Ospa(two, est, 10.0, 1.0), 7.5, kPointTol);
  // Conventions: both empty 0, one empty c.
  EXPECT_EQ(Ospa({}, {}, 10.0, 2.0), 0.0);
  EXPECT_EQ(Ospa(one, {}, 10.0, 2.0), 10.0);
  EXPECT_EQ(Ospa({}, est, 10.0, 2.0), 10.0);
}

TEST(Gospa, HandCheckedValues) {
  const std::vector<IdPoint> two = {{1, 0, 0}, {2, 100, 0}};
  const std::vector<IdPoint> est = {{7, 3, 4}};
  // c = 10, p = 2: localisation 5^2 = 25, one missed truth c^2/2 = 50: sqrt(75).
  const GospaTerms g = Gospa(two, est, 10.0, 2.0);
  EXPECT_NEAR(g.localisation, 25.0, kPointTol);
  EXPECT_NEAR(g.missed, 50.0, kPointTol);
  EXPECT_EQ(g.false_alarm, 0.0);
  EXPECT_EQ(g.num_assigned, 1);
  EXPECT_NEAR(g.distance, std::sqrt(75.0), kPointTol);
  // A pair at d = 20 >= c = 10 counts as one missed + one false: sqrt(50 + 50) = 10.
  const std::vector<IdPoint> far = {{7, 20, 0}};
  const GospaTerms h = Gospa({two.data(), 1}, far, 10.0, 2.0);
  EXPECT_EQ(h.num_missed, 1);
  EXPECT_EQ(h.num_false, 1);
  EXPECT_NEAR(h.distance, 10.0, kPointTol);
}

// Switching term, c = 10, p = 1, gamma = 2:
// f1: truths 1 @ (0,0), 2 @ (100,0); estimates a(=10) @ (0,0), b(=11) @ (100,0): 1->a, 2->b. 0.
// f2: a @ (100,0), b @ (0,0): 1->b, 2->a, two full switches: 2 * 2^1 = 4; distance 4.
// f3: only a @ (100,0): 1 unassigned (half switch 0.5), 2->a unchanged: missed c/2 = 5,
//     switching 2 * 0.5 = 1, distance 6. Mean GOSPA (0 + 4 + 6) / 3, total switches 2.5.
// OSPA per frame: 0, 0, (0 + 10 * 1) / 2 = 5.
TEST(Gospa, SwitchingTerm) {
  std::vector<PointFrame> frames(3);
  for (auto& f : frames) f.truth = {{1, 0, 0}, {2, 100, 0}};
  frames[0].estimate = {{10, 0, 0}, {11, 100, 0}};
  frames[1].estimate = {{10, 100, 0}, {11, 0, 0}};
  frames[2].estimate = {{10, 100, 0}};
  const PointMetrics m =
      ComputePointMetrics(frames, {.cutoff_px = 10, .order = 1, .switching_penalty = 2});
  ASSERT_EQ(m.gospa.size(), 3u);
  EXPECT_NEAR(m.gospa[0].distance, 0.0, kPointTol);
  EXPECT_NEAR(m.gospa[1].distance, 4.0, kPointTol);
  EXPECT_NEAR(m.gospa[2].distance, 6.0, kPointTol);
  EXPECT_NEAR(m.total_switches, 2.5, kPointTol);
  EXPECT_NEAR(m.mean_gospa, 10.0 / 3.0, kPointTol);
  EXPECT_NEAR(m.ospa[2], 5.0, kPointTol);
  EXPECT_NEAR(m.mean_ospa, 5.0 / 3.0, kPointTol);
  // Without the term the switches cost nothing.
  const PointMetrics plain = ComputePointMetrics(frames, {.cutoff_px = 10, .order = 1});
  EXPECT_NEAR(plain.gospa[1].distance, 0.0, kPointTol);
  EXPECT_NEAR(plain.gospa[2].distance, 5.0, kPointTol);
}

TEST(PointMetricsOptions, DefaultsValidateAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(PointMetricsOptions{}.Validate());
  try {
    PointMetricsOptions{.order = 0.5}.Validate();
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("metrics.ospa_order"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PointMetricsOptions{.cutoff_px = 0}.Validate(), InputError);
  EXPECT_THROW(PointMetricsOptions{.switching_penalty = -1}.Validate(), InputError);
}

// c^p and γ^p must fit a double with room for a frame's sums (an audit of
// valid input: c = 10^6 with p = 60 gave NaN for every frame, exit 0). At
// p = 50 (c^p = 1e300) a frame of one missed truth and one far estimate
// still gives the hand-checked OSPA c and GOSPA (c^p / 2 * 2)^(1/p) = c.
TEST(PointMetricsOptions, PowersPastWhatADoubleHoldsAreRefused) {
  const auto refused = [](const PointMetricsOptions& o, const std::string& expected) {
    try {
      o.Validate();
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused({.cutoff_px = 1e6, .order = 60},
          "metrics.ospa_order: expected an order p with ospa_cutoff_px^p at most 1e300 (p at "
          "most 50 with that cut-off");
  refused({.cutoff_px = 10, .order = 100, .switching_penalty = 1e4},
          "gospa_switching_penalty^p at most 1e300 (p at most 75 with that penalty");
  const PointMetricsOptions edge{.cutoff_px = 1e6, .order = 50};
  EXPECT_NO_THROW(edge.Validate());
  const std::vector<IdPoint> truth = {{1, 0, 0}};
  const std::vector<IdPoint> far = {{7, 3e6, 0}};
  EXPECT_NEAR(Ospa(truth, far, edge.cutoff_px, edge.order), 1e6, 1e-6);  // rounding of pow
  EXPECT_NEAR(Gospa(truth, far, edge.cutoff_px, edge.order).distance, 1e6, 1e-6);
  EXPECT_NO_THROW((PointMetricsOptions{.cutoff_px = 1000, .order = 100}.Validate()));
}

TEST(PointMetrics, CentresFromSequence) {
  Sequence seq;
  seq.frames.resize(1);
  seq.frames[0].gt.push_back({3, {0, 0, 10, 20}});
  const auto frames = PointFramesFromSequence(seq);
  ASSERT_EQ(frames[0].truth.size(), 1u);
  EXPECT_EQ(frames[0].truth[0].x, 5.0);
  EXPECT_EQ(frames[0].truth[0].y, 10.0);
}

}  // namespace
}  // namespace hcpf::metrics
