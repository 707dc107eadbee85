// Direction of arrival from arrival-time differences across a receiver array
// (docs/tof-measurements.md#direction-of-arrival).
//
// Plane wave from direction u(beta) = (cos beta, sin beta) (robot frame,
// pointing from the robot toward the source): receiver i at r_i hears it at
//     t_i = t0 - r_i . u(beta) / c,        so  t_i - t_j = -(r_i - r_j) . u / c,
// t0 being the time the wavefront passes the robot origin. Weighted least
// squares over (t0, beta): for a given beta the best t0 is the weighted mean
// of t_i + r_i . u / c, which leaves a one-dimensional, smooth cost in beta,
// searched on a 0.5 degree grid and refined by golden section. Two receivers
// give two mirror solutions of zero residual; the one the receivers face
// wins (as it does whenever two minima are within one unit of chi^2).
#pragma once

#include <span>
#include <vector>

#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::tof {

// One receiver's compensated arrival time (any common origin) and its
// standard deviation.
struct TimedHit {
  int channel = 0;
  double time_s = 0;
  double sd_s = 1e-6;
};

struct PlaneWaveFit {
  Doa doa;          // valid with two or more receivers
  double t0_s = 0;  // wavefront at the robot origin
  double t0_sd_s = 0;
  struct Hit {
    double residual_s = 0;  // t_i - (t0 - r_i . u / c)
    bool used = true;       // kept in the fit
  };
  std::vector<Hit> hits;      // per input hit, in input order
  double chi2 = 0;            // sum of squared normalised residuals of the used hits
  int dof = 0;                // used hits - 2
  bool inconsistent = false;  // chi2 beyond its 99.9 % point (dof >= 1), or two
                              // receivers further apart in time than in space
};

struct PlaneWaveOptions {
  double speed_of_sound_mps = 343.2;
  // A single receiver gives no direction: the source is assumed within this
  // half-angle of its axis (uniform), which sets t0's uncertainty.
  double single_half_angle_rad = 0.785398163397448;  // 45 degrees
  // With four or more hits, an inconsistent fit drops its worst hit and
  // refits while at least three remain.
  bool reject_outliers = true;
};

// Throws std::invalid_argument on a channel outside the array or a
// non-finite time or deviation. An empty span gives an invalid fit.
PlaneWaveFit fit_plane_wave(const ReceiverArray& array, std::span<const TimedHit> hits,
                            const PlaneWaveOptions& options);

// Angle a - b wrapped to (-pi, pi].
double angle_difference(double a, double b);

}  // namespace odoloc::sw::tof
