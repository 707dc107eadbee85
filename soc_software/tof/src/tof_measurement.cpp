#include "odoloc/sw/tof_measurement.hpp"

#include <algorithm>
#include <array>
#include <numbers>
#include <utility>

namespace odoloc::sw::tof {

ReceiverArray ReceiverArray::polygon(int n, double side_m, double first_axis_rad) {
  if (n < 1 || n > 32)
    throw std::invalid_argument("ReceiverArray::polygon: 1..32 receivers, got " +
                                std::to_string(n));
  if (!(std::isfinite(side_m) && side_m > 0) || !std::isfinite(first_axis_rad))
    throw std::invalid_argument("ReceiverArray::polygon: side must be finite and positive");
  ReceiverArray array;
  const double apothem = n >= 3 ? side_m / (2 * std::tan(std::numbers::pi / n)) : side_m / 2;
  for (int i = 0; i < n; ++i) {
    const double a = first_axis_rad + 2 * std::numbers::pi * i / n;
    array.receivers.push_back({{apothem * std::cos(a), apothem * std::sin(a)}, a});
  }
  return array;
}

double ReceiverArray::aperture_m() const {
  double widest = 0;
  for (const Receiver& a : receivers)
    for (const Receiver& b : receivers)
      widest = std::max(
          widest, std::hypot(a.position_m.x - b.position_m.x, a.position_m.y - b.position_m.y));
  return widest;
}

void ReceiverArray::validate() const {
  if (receivers.empty() || receivers.size() > 32)
    throw std::invalid_argument("ReceiverArray: 1..32 receivers (one per capture channel), got " +
                                std::to_string(receivers.size()));
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const Receiver& r = receivers[i];
    if (!std::isfinite(r.position_m.x) || !std::isfinite(r.position_m.y) ||
        !std::isfinite(r.axis_rad))
      throw std::invalid_argument("ReceiverArray: receiver " + std::to_string(i) +
                                  " has a non-finite position or axis");
    if (std::hypot(r.position_m.x, r.position_m.y) > 10.0)
      throw std::invalid_argument("ReceiverArray: receiver " + std::to_string(i) +
                                  " is more than 10 m from the robot origin");
    for (std::size_t j = 0; j < i; ++j)
      if (std::hypot(r.position_m.x - receivers[j].position_m.x,
                     r.position_m.y - receivers[j].position_m.y) < 1e-4)
        throw std::invalid_argument("ReceiverArray: receivers " + std::to_string(j) + " and " +
                                    std::to_string(i) + " are at the same place");
  }
}

namespace {
constexpr std::array<std::pair<Flag, std::string_view>, 33> kFlagNames{{
    {Flag::kMissing, "missing"},
    {Flag::kEarlyRejected, "early_rejected"},
    {Flag::kEchoSuspect, "echo_suspect"},
    {Flag::kEchoes, "echoes"},
    {Flag::kOccludedSuspect, "occluded_suspect"},
    {Flag::kOverflow, "overflow"},
    {Flag::kLostEvents, "lost_events"},
    {Flag::kStuckChannel, "stuck_channel"},
    {Flag::kUnwrapAmbiguous, "unwrap_ambiguous"},
    {Flag::kOutOfOrder, "out_of_order"},
    {Flag::kDeadChannel, "dead_channel"},
    {Flag::kNoise, "noise"},
    {Flag::kSingleReceiver, "single_receiver"},
    {Flag::kDoaInconsistent, "doa_inconsistent"},
    {Flag::kResynchronised, "resynchronised"},
    {Flag::kCoasted, "coasted"},
    {Flag::kDoublePulseMissing, "double_pulse_missing"},
    {Flag::kDoublePulseMisplaced, "double_pulse_misplaced"},
    {Flag::kLockLost, "lock_lost"},
    {Flag::kReferenceSuspect, "reference_suspect"},
    {Flag::kSaturated, "saturated"},
    {Flag::kMergedPulse, "merged_pulse"},
    {Flag::kBeforeBound, "before_bound"},
    {Flag::kSyncMissing, "sync_missing"},
    {Flag::kExtraSync, "extra_sync"},
    {Flag::kOutlier, "outlier"},
    {Flag::kAmbiguous, "ambiguous"},
    {Flag::kCarrierIrregular, "carrier_irregular"},
    {Flag::kEdgesMissing, "edges_missing"},
    {Flag::kWeak, "weak"},
    {Flag::kOutOfRange, "out_of_range"},
    {Flag::kInvalid, "invalid"},
    {Flag::kCycleUnverified, "cycle_unverified"},
}};
}  // namespace

std::string_view flag_name(Flag f) {
  for (const auto& [flag, name] : kFlagNames)
    if (flag == f)
      return name;
  return "?";
}

std::string to_string(Flags flags) {
  std::string out;
  for (const auto& [flag, name] : kFlagNames) {
    if (!flags.has(flag))
      continue;
    if (!out.empty())
      out += '|';
    out += name;
  }
  return out.empty() ? "none" : out;
}

Flag incident_flag(IncidentKind kind) {
  switch (kind) {
    case IncidentKind::kOverflow:
      return Flag::kOverflow;
    case IncidentKind::kLostEvents:
      return Flag::kLostEvents;
    case IncidentKind::kStuckHigh:
      return Flag::kStuckChannel;
    case IncidentKind::kUnwrapAmbiguous:
      return Flag::kUnwrapAmbiguous;
  }
  return Flag::kInvalid;
}

}  // namespace odoloc::sw::tof
