#pragma once
// What differentiating a quantized position puts into an equation-error residual (issue 45, item 4; DIAGNOSIS.md,
// "The noise floor, and leaks").
//
// An encoder reports the position on a lattice of step q. The quantization error is small in position (q/√12 RMS when
// the motion crosses many counts: Widrow & Kollár, Quantization Noise, 2008, ch. 4)
// but the derivatives multiply it by (2πf)² up to the derivative's cut-off: inside the motion's band, in the
// acceleration that the inverse model multiplies by the mass, it can exceed the force sensor's own noise (a
// 2¹⁸-count rotary encoder at 1 kHz: ten times). The spectral floor (EstimateNoiseFloor) reads the residual in its
// quietest segments, where the axis rests and the count does not change, and misses it. Here it is measured by
// re-quantizing the record's own motion: the low-passed position is put on the lattice again at several offsets,
// differentiated as the log's motion was (DeriveMotion), and the difference from the smooth motion's derivatives is
// carried to the output by the model's own sensitivities to acceleration and velocity. That part of the residual is
// not physics: a candidate whose regressors carry the same quantization noise (a delayed model output, a product
// with ŷ) can fit it on held-out data too, and that is a leak.

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

// The lattice step of a quantized signal: the smallest gap between two of its distinct values [the signal's unit]
// (an encoder's count, a logged number's last digit). 0 when all values are equal. A lower bound: a signal that is not
// quantized has gaps far below its noise and gives a negligible step. N >= 1; throws nothing.
double QuantizationStep(const Eigen::Ref<const Eigen::VectorXd>& signal);

struct QuantizationFloor {
  double step = 0.0;         // q [unit of the position]; 0 = none seen
  double mass = 0.0;         // ∂ŷ/∂a, the model output's sensitivity to acceleration [output unit per m/s²]
  double damping = 0.0;      // ∂ŷ/∂v [output unit per m/s]
  double rms = 0.0;          // the part of the residual it makes [output unit, RMS]
};

// The quantization floor of an equation-error record (signals.position the logged position, signals.velocity and
// .acceleration derived from it by DeriveMotion at cutoff_hz, signals.model_output the model's ŷ from them). The
// sensitivities are the least-squares coefficients of ŷ on (a, v, sign v, 1); the residual's part is the RMS over four
// lattice offsets (q·(k + ½)/4) of mass·δa + damping·δv. A lower estimate: a steep friction law's response to the
// velocity's quantization noise near rest is not in it (it is the friction law's to explain, see the law
// replacements). All zero when cutoff_hz <= 0 (simulation mode: the position itself is compared, its quantization is
// the white q/√12), when there is no model output, or when the position takes a single value. Throws as DeriveMotion.
QuantizationFloor EstimateQuantizationFloor(const DiagnosisSignals& signals, double cutoff_hz);

// The encoder's share of the derived acceleration at a cut-off: the RMS of what re-quantizing the low-passed position
// (two lattice offsets) changes in its acceleration over the RMS of the acceleration derived from the logged position,
// both by DeriveMotion at cutoff_hz. 0 when the position shows no lattice or does not accelerate. Scale-free (metres,
// radians, volts alike). Throws as DeriveMotion.
double QuantizationShareOfAcceleration(const Eigen::VectorXd& time, const Eigen::VectorXd& position, double cutoff_hz);

// At most this share of the derived acceleration may be the encoder's quantization (QuantizationLimitedCutoff).
inline constexpr double kMaxQuantizationShare = 0.1;
// The cut-off is lowered at most this many times by a factor of 2 (in steps of √2).
inline constexpr int kCutoffHalvings = 3;

// The derivative cut-off a coarse encoder allows: the highest of cutoff_hz·2^(−k/2), k = 0 … 2·kCutoffHalvings, at
// which the quantization's share of the derived acceleration (QuantizationShareOfAcceleration) is at most
// kMaxQuantizationShare; the lowest when none is. The acceleration's quantization noise grows as f_c^2.5 while the
// motion's own acceleration stops growing above its band: the cut-off comes down to where the motion still dominates
// (IDIM-LS practice: the derivatives' low-pass sits above the motion's band and below the sensor's noise; Gautier,
// Janot, Vandanjon 2013, IEEE TCST 21(2)).
// share (optional) receives the share at the cut-off returned. Throws as DeriveMotion.
double QuantizationLimitedCutoff(const Eigen::VectorXd& time, const Eigen::VectorXd& position, double cutoff_hz,
                                 double* share = nullptr);

// The record's floor with the quantization part in: fills floor->quantization_rms and ->position_step, and
// floor->rms = √(white_rms² + quantization_rms²) (unchanged when there is no quantization part). Throws as above.
void AddQuantizationFloor(const DiagnosisSignals& signals, double cutoff_hz, NoiseFloor* floor);

}  // namespace mb
