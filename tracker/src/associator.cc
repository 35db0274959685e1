#include "hcpf/tracker/associator.h"

#include <algorithm>
#include <limits>
#include <tuple>

#include "hcpf/core/check.h"
#include "hcpf/tracker/hungarian.h"

namespace hcpf::tracker {

std::span<const Field<AssociationOptions>> AssociationOptions::Fields() {
  using O = AssociationOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::method>("method", "gnn (Hungarian), nearest (greedy) or none"),
      ChoiceField<&O::gate>("gate", "which gate a detection must pass"),
      NumberField("gate_mahalanobis_sq", &O::gate_mahalanobis_sq, Closed(1e-6, 1e6), "",
                  "squared Mahalanobis gate (9.21 = χ²(2) at 99 %)"),
      NumberField("measurement_sigma_px", &O::measurement_sigma_px, Closed(1e-3, 1e4), "px",
                  "measurement noise added to the filter's covariance"),
      NumberField("min_iou", &O::min_iou, Closed(0, 1), "", "gate iou: least IoU"),
  };
  return fields;
}

void AssociationOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

std::optional<double> GatedCost(const TrackPrediction& track, const Detection& detection,
                                const AssociationOptions& options) {
  // A box with a non-finite side is no position (a broken detector output):
  // never gated in, as the likelihoods ignore it. The IoU's min and max let
  // a NaN left through (a review: it passed at IoU 0.6, counted as the
  // filter's support).
  if (!detection.box.finite()) return std::nullopt;
  if (options.gate == GateKind::kIou) {
    const double iou = Iou(track.box, detection.box);
    if (iou < options.min_iou || iou <= 0.0) return std::nullopt;
    return 1.0 - iou;
  }
  const double r2 = options.measurement_sigma_px * options.measurement_sigma_px;
  const double sxx = track.cov(0, 0) + r2;
  const double sxy = 0.5 * (track.cov(0, 1) + track.cov(1, 0));
  const double syy = track.cov(1, 1) + r2;
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 0.0) || !std::isfinite(det)) return std::nullopt;
  const double dx = detection.box.centre_x() - track.mean.x();
  const double dy = detection.box.centre_y() - track.mean.y();
  // d^T S^-1 d with S^-1 = [[syy, -sxy], [-sxy, sxx]] / det.
  const double d2 = (syy * dx * dx - 2.0 * sxy * dx * dy + sxx * dy * dy) / det;
  if (!(d2 <= options.gate_mahalanobis_sq)) return std::nullopt;
  return d2;
}

namespace {

std::vector<double> CostMatrix(std::span<const TrackPrediction> tracks,
                               std::span<const Detection> detections,
                               const AssociationOptions& options) {
  std::vector<double> cost(tracks.size() * detections.size(),
                           std::numeric_limits<double>::infinity());
  for (size_t t = 0; t < tracks.size(); ++t) {
    for (size_t d = 0; d < detections.size(); ++d) {
      if (auto c = GatedCost(tracks[t], detections[d], options)) {
        cost[t * detections.size() + d] = *c;
      }
    }
  }
  return cost;
}

}  // namespace

GnnAssociator::GnnAssociator(const AssociationOptions& options) : options_(options) {
  options_.Validate();
}

std::vector<int> GnnAssociator::Associate(std::span<const TrackPrediction> tracks,
                                          std::span<const Detection> detections) const {
  const std::vector<double> cost = CostMatrix(tracks, detections, options_);
  return SolveAssignment(cost, static_cast<int>(tracks.size()),
                         static_cast<int>(detections.size()));
}

NearestNeighbourAssociator::NearestNeighbourAssociator(const AssociationOptions& options)
    : options_(options) {
  options_.Validate();
}

std::vector<int> NearestNeighbourAssociator::Associate(
    std::span<const TrackPrediction> tracks, std::span<const Detection> detections) const {
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t t = 0; t < tracks.size(); ++t) {
    for (size_t d = 0; d < detections.size(); ++d) {
      if (auto c = GatedCost(tracks[t], detections[d], options_)) pairs.emplace_back(*c, t, d);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> assignment(tracks.size(), -1);
  std::vector<char> taken(detections.size(), 0);
  for (const auto& [c, t, d] : pairs) {
    if (assignment[t] != -1 || taken[d]) continue;
    assignment[t] = static_cast<int>(d);
    taken[d] = 1;
  }
  return assignment;
}

std::vector<uint8_t> Associator::Evidence(std::span<const TrackPrediction> tracks,
                                          std::span<const Detection>,
                                          std::span<const int> assignment) const {
  std::vector<uint8_t> out(tracks.size(), 0);
  for (size_t t = 0; t < tracks.size(); ++t) out[t] = assignment[t] >= 0 ? 1 : 0;
  return out;
}

NoAssociator::NoAssociator(const AssociationOptions& options) : options_(options) {
  options_.Validate();
}

std::vector<uint8_t> NoAssociator::Evidence(std::span<const TrackPrediction> tracks,
                                            std::span<const Detection> detections,
                                            std::span<const int>) const {
  std::vector<uint8_t> out(tracks.size(), 0);
  for (size_t t = 0; t < tracks.size(); ++t) {
    out[t] = std::any_of(
                 detections.begin(), detections.end(),
                 [&](const Detection& d) { return GatedCost(tracks[t], d, options_).has_value(); })
                 ? 1
                 : 0;
  }
  return out;
}

std::unique_ptr<Associator> MakeAssociator(const AssociationOptions& options) {
  options.Validate();
  switch (options.method) {
    case AssociationMethod::kGlobalNearestNeighbour:
      return std::make_unique<GnnAssociator>(options);
    case AssociationMethod::kNearestNeighbour:
      return std::make_unique<NearestNeighbourAssociator>(options);
    case AssociationMethod::kNone:
      return std::make_unique<NoAssociator>(options);
  }
  HCPF_CHECK(false) << "unknown association method";
  return nullptr;
}

}  // namespace hcpf::tracker
