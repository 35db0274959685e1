#pragma once
// Data association: which detection (if any) belongs to which filter.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/types.h"

namespace hcpf::tracker {

enum class AssociationMethod {
  kGlobalNearestNeighbour,  // "gnn": Hungarian on gated costs
  kNearestNeighbour,        // "nearest": greedy, cheapest gated pair first
  kNone,                    // "none": no association
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::AssociationMethod> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::AssociationMethod::kGlobalNearestNeighbour, std::string_view("gnn")},
      std::pair{hcpf::tracker::AssociationMethod::kNearestNeighbour, std::string_view("nearest")},
      std::pair{hcpf::tracker::AssociationMethod::kNone, std::string_view("none")}};
};

namespace hcpf::tracker {

enum class GateKind {
  kMahalanobis,  // "mahalanobis": d^T (Sigma + sigma_px^2 I)^-1 d <= gate
  kIou,          // "iou": IoU(predicted box, detection box) >= min_iou
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::GateKind> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::GateKind::kMahalanobis, std::string_view("mahalanobis")},
      std::pair{hcpf::tracker::GateKind::kIou, std::string_view("iou")}};
};

namespace hcpf::tracker {

struct AssociationOptions {
  AssociationMethod method = AssociationMethod::kGlobalNearestNeighbour;
  GateKind gate = GateKind::kMahalanobis;
  // Squared Mahalanobis gate; 9.21 is the 99% quantile of chi-square with 2
  // degrees of freedom.
  double gate_mahalanobis_sq = 9.21;
  // Detection centre noise added to the filter covariance in the gate, px.
  double measurement_sigma_px = 3.0;
  // IoU gate (gate = iou): minimum overlap.
  double min_iou = 0.1;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<AssociationOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.association") const;
};

// What the associator sees of one filter after its predict step.
struct TrackPrediction {
  TrackId id{};
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  // box centre, px
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();   // px^2
  BoxPx box;                                       // predicted box
};

// Gate test and cost of pairing a prediction with a detection: the squared
// Mahalanobis distance (gate = mahalanobis) or 1 - IoU (gate = iou);
// nullopt when outside the gate.
std::optional<double> GatedCost(const TrackPrediction& track, const Detection& detection,
                                const AssociationOptions& options);

// Contract: returns one entry per track: the index of its detection or -1;
// every detection is given to at most one track; only gated pairs are made.
// Deterministic (no randomness), stateless and const.
class Associator {
 public:
  virtual ~Associator() = default;
  virtual std::vector<int> Associate(std::span<const TrackPrediction> tracks,
                                     std::span<const Detection> detections) const = 0;
  // Per track, whether the detections hold evidence for it (1) or not (0):
  // by default the detection `Associate` gave it; an associator that pairs
  // nothing says which tracks have a detection inside their gate. The
  // likelihood turns this into the filter's support (LikelihoodInput).
  virtual std::vector<uint8_t> Evidence(std::span<const TrackPrediction> tracks,
                                        std::span<const Detection> detections,
                                        std::span<const int> assignment) const;
  virtual std::string_view name() const = 0;
};

// Global nearest neighbour: minimum total gated cost over all tracks
// (SolveAssignment), maximising the number of gated pairs first.
class GnnAssociator final : public Associator {
 public:
  explicit GnnAssociator(const AssociationOptions& options);
  std::vector<int> Associate(std::span<const TrackPrediction> tracks,
                             std::span<const Detection> detections) const override;
  std::string_view name() const override { return "gnn"; }

 private:
  AssociationOptions options_;
};

// Greedy nearest neighbour: repeatedly pairs the cheapest remaining gated
// (track, detection) pair (ties: lower track index, then lower detection index).
class NearestNeighbourAssociator final : public Associator {
 public:
  explicit NearestNeighbourAssociator(const AssociationOptions& options);
  std::vector<int> Associate(std::span<const TrackPrediction> tracks,
                             std::span<const Detection> detections) const override;
  std::string_view name() const override { return "nearest"; }

 private:
  AssociationOptions options_;
};

// No association: every track gets -1; a track has evidence when any
// detection lies inside its gate (GatedCost).
class NoAssociator final : public Associator {
 public:
  explicit NoAssociator(const AssociationOptions& options = {});
  std::vector<int> Associate(std::span<const TrackPrediction> tracks,
                             std::span<const Detection>) const override {
    return std::vector<int>(tracks.size(), -1);
  }
  std::vector<uint8_t> Evidence(std::span<const TrackPrediction> tracks,
                                std::span<const Detection> detections,
                                std::span<const int> assignment) const override;
  std::string_view name() const override { return "none"; }

 private:
  AssociationOptions options_;
};

std::unique_ptr<Associator> MakeAssociator(const AssociationOptions& options);

}  // namespace hcpf::tracker
