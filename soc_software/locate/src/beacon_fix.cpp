#include "odoloc/sw/beacon_fix.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odoloc::sw::locate {

namespace {

double cross(Vec2 o, Vec2 a, Vec2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  const double t =
      len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

// Andrew's monotone chain: the hull counter-clockwise, collinear points dropped.
std::vector<Vec2> convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(),
            [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (points.size() < 3)
    return points;
  std::vector<Vec2> hull(2 * points.size());
  std::size_t k = 0;
  for (const Vec2 p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0)
      --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
      --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// A usable number: finite distance, finite non-negative deviation.
bool finite(const RangeCandidate& c) {
  return std::isfinite(c.distance_m) && std::isfinite(c.sd_m) && c.sd_m >= 0;
}

}  // namespace

void BeaconLayout::validate() const {
  if (beacons.size() > 64)
    throw std::invalid_argument("BeaconLayout: at most 64 beacons, got " +
                                std::to_string(beacons.size()));
  for (std::size_t i = 0; i < beacons.size(); ++i) {
    const Beacon& b = beacons[i];
    if (!std::isfinite(b.position_m.x) || !std::isfinite(b.position_m.y) ||
        !std::isfinite(b.height_m))
      throw std::invalid_argument("BeaconLayout: beacon " + std::to_string(i) +
                                  " has a non-finite position or height");
    for (std::size_t j = 0; j < i; ++j)
      if (std::hypot(b.position_m.x - beacons[j].position_m.x,
                     b.position_m.y - beacons[j].position_m.y) < 1e-3)
        throw std::invalid_argument("BeaconLayout: beacons " + std::to_string(j) + " and " +
                                    std::to_string(i) + " are at the same place");
  }
}

double BeaconLayout::range_m(std::size_t beacon, Vec2 p) const {
  const Beacon& b = beacons.at(beacon);
  return std::sqrt((p.x - b.position_m.x) * (p.x - b.position_m.x) +
                   (p.y - b.position_m.y) * (p.y - b.position_m.y) + b.height_m * b.height_m);
}

double BeaconLayout::distance_outside_hull_m(Vec2 p) const {
  return ConvexHull(*this).distance_outside_m(p);
}

ConvexHull::ConvexHull(const BeaconLayout& layout) {
  std::vector<Vec2> points;
  points.reserve(layout.beacons.size());
  for (const Beacon& b : layout.beacons)
    points.push_back(b.position_m);
  vertices_ = convex_hull(std::move(points));
}

double ConvexHull::distance_outside_m(Vec2 p) const {
  const std::vector<Vec2>& hull = vertices_;
  if (hull.empty())
    return std::numeric_limits<double>::infinity();
  if (hull.size() == 1)
    return std::hypot(p.x - hull[0].x, p.y - hull[0].y);
  bool inside = hull.size() >= 3;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec2 a = hull[i];
    const Vec2 b = hull[(i + 1) % hull.size()];
    if (cross(a, b, p) < 0)
      inside = false;
    nearest = std::min(nearest, distance_to_segment(p, a, b));
  }
  return inside ? 0.0 : nearest;
}

RangeSet range_set(const tof::CycleMeasurement& cycle) {
  RangeSet set;
  set.speed_of_sound_mps = cycle.speed_of_sound_mps;
  set.beacons.reserve(cycle.beacons.size());
  for (const tof::BeaconMeasurement& m : cycle.beacons) {
    BeaconRange range;
    range.primary = m.primary;
    range.flags = m.flags | cycle.flags;
    for (const tof::Arrival& a : m.candidates)
      range.candidates.push_back({a.distance_m, a.sd_m, a.flags});
    set.beacons.push_back(std::move(range));
  }
  return set;
}

int Fix::used() const {
  return static_cast<int>(std::count_if(beacons.begin(), beacons.end(), [](const BeaconUse& u) {
    return u.status == BeaconStatus::kUsed;
  }));
}

std::string_view name(Solver solver) {
  switch (solver) {
    case Solver::kKleemanTriple:
      return "kleeman_triple";
    case Solver::kLongsolve:
      return "longsolve";
    case Solver::kGaussNewton:
      return "gauss_newton";
    case Solver::kThammaTrilateration:
      return "thamma_trilateration";
    case Solver::kThammaLeastSquares:
      return "thamma_least_squares";
  }
  return "?";
}

std::string_view name(NoFixReason reason) {
  switch (reason) {
    case NoFixReason::kNone:
      return "none";
    case NoFixReason::kNonFiniteInput:
      return "non_finite_input";
    case NoFixReason::kTooFewBeacons:
      return "too_few_beacons";
    case NoFixReason::kDegenerateGeometry:
      return "degenerate_geometry";
    case NoFixReason::kOutsideHull:
      return "outside_hull";
    case NoFixReason::kNotConverged:
      return "not_converged";
    case NoFixReason::kMirrorAmbiguous:
      return "mirror_ambiguous";
    case NoFixReason::kInconsistent:
      return "inconsistent";
    case NoFixReason::kAmbiguousBeaconSets:
      return "ambiguous_beacon_sets";
  }
  return "?";
}

std::string_view name(BeaconStatus status) {
  switch (status) {
    case BeaconStatus::kUsed:
      return "used";
    case BeaconStatus::kNotInLayout:
      return "not_in_layout";
    case BeaconStatus::kMissing:
      return "missing";
    case BeaconStatus::kNonFinite:
      return "non_finite";
    case BeaconStatus::kTriangleInequality:
      return "triangle_inequality";
    case BeaconStatus::kTripleDeviation:
      return "triple_deviation";
    case BeaconStatus::kOutlier:
      return "outlier";
    case BeaconStatus::kUnused:
      return "unused";
  }
  return "?";
}

Prepared prepare(const BeaconLayout& layout, const RangeSet& ranges, double min_sd_m) {
  Prepared out;
  out.uses.reserve(ranges.beacons.size());
  for (std::size_t i = 0; i < ranges.beacons.size(); ++i) {
    const BeaconRange& range = ranges.beacons[i];
    BeaconUse use;
    use.beacon = static_cast<int>(i);
    const bool has_primary =
        range.primary >= 0 && static_cast<std::size_t>(range.primary) < range.candidates.size();
    if (i >= layout.beacons.size()) {
      use.status = BeaconStatus::kNotInLayout;
    } else if (!has_primary || range.flags.has(Flag::kMissing) ||
               (range.candidates[static_cast<std::size_t>(range.primary)].flags.bits() &
                kUnusableFlags.bits()) != 0) {
      use.status = BeaconStatus::kMissing;
    } else if (const RangeCandidate& c = range.candidates[static_cast<std::size_t>(range.primary)];
               !finite(c)) {
      use.status = BeaconStatus::kNonFinite;
      out.any_non_finite = true;
    } else {
      use.status = BeaconStatus::kUsed;
      use.candidate = range.primary;
      out.primaries.push_back({use.beacon, range.primary, c.distance_m, std::max(c.sd_m, min_sd_m),
                               ((c.flags | range.flags).bits() & kSuspectFlags.bits()) != 0});
    }
    out.uses.push_back(use);
  }
  return out;
}

void settle_unused(Fix& fix) {
  if (fix.valid || (std::isfinite(fix.position_m.x) && std::isfinite(fix.position_m.y)))
    return;
  for (BeaconUse& u : fix.beacons)
    if (u.status == BeaconStatus::kUsed) {
      u.status = BeaconStatus::kUnused;
      u.candidate = -1;
    }
}

std::vector<Observation> alternatives(const RangeSet& ranges, int beacon, double min_sd_m) {
  std::vector<Observation> out;
  if (beacon < 0 || static_cast<std::size_t>(beacon) >= ranges.beacons.size())
    return out;
  const BeaconRange& range = ranges.beacons[static_cast<std::size_t>(beacon)];
  for (std::size_t k = static_cast<std::size_t>(std::max(range.primary, -1) + 1);
       k < range.candidates.size(); ++k) {
    const RangeCandidate& c = range.candidates[k];
    if (!finite(c) || (c.flags.bits() & kUnusableFlags.bits()) != 0)
      continue;
    out.push_back({beacon, static_cast<int>(k), c.distance_m, std::max(c.sd_m, min_sd_m),
                   (c.flags.bits() & kSuspectFlags.bits()) != 0});
  }
  return out;
}

}  // namespace odoloc::sw::locate
