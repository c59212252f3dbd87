#pragma once
// The grammar's modulator "time_chirp" (factors.h): a vibration whose frequency drifts linearly in time — a pump or a
// fan speeding up, a neighbouring machine changing speed: f(t) = f₀ + ḟ·t, its phase the integral
// φ(t) = 2π(f₀t + ½ḟt²). Its columns are cos kφ, sin kφ (PeriodicColumns on the phase in cycles, period 1); the block
// that adds it is time_periodic with its frequency_rate (blocks/time_periodic.h).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/factors.h"

namespace mb {

class ProposalContext;

/// The phase in cycles, f₀·t + ½·ḟ·t² (N), at the instants t [s] (N), for the frequency f₀ [Hz] at t = 0 and its
/// rate ḟ [Hz/s]: the phase of time_periodic's sine with its frequency_rate. Throws nothing.
Eigen::VectorXd ChirpCycles(const Eigen::VectorXd& t, double f0, double rate);

/// The modulator's shape scan: the residual demodulated by the multiplier column m (N; ones for the vibration alone)
/// is followed along the ridge of its short-time spectrum (Hann windows of a sixth of the record, half overlapping).
/// A straight line f = a + b·(t − t_m) through the windows whose peak stands 8 × above their median (at least 5) is
/// proposed when it drifts by more than 3 of a window's bins over the record (less: one fixed frequency, the
/// time_periodic modulator's) and stays within 1.5 bins of the ridge (else a note naming `pair`); the rate is refined
/// by dechirping — the rate whose dechirped spectrum, r·m·exp(−iπḟ(t − t_m)²), peaks highest (Kay, "Fundamentals of
/// Statistical Signal Processing: Estimation Theory", 1993, §13.6) — and both by golden-section searches of the joint
/// fit with the base. Returns zero or one parameter set {frequency_hz f₀ [Hz] at t = 0, drift_rate ḟ [Hz/s],
/// harmonics 1}; none when the line reaches 0 Hz within the record (with a note). Throws what the joint fit throws.
std::vector<FactorParameters> ScanTimeChirp(ProposalContext& context, const Eigen::VectorXd& m, const std::string& pair);

}  // namespace mb
