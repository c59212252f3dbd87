#pragma once
// Building blocks of the effects' regressors (models/diagnosis/effects/): parameter access with the catalogue's
// error messages, sign(v) with a dead band, Fourier columns.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"

namespace mb {

struct EffectTraits;  // models/diagnosis/effect_registry.h

/// The parameter `key` of the effect. Throws std::invalid_argument "effect 'x': parameter 'key' is missing or not
/// finite; set it (SI units)".
double RequiredParameter(const EffectInstance& effect, const char* key);
/// As RequiredParameter, and > 0 (else std::invalid_argument naming it).
double PositiveParameter(const EffectInstance& effect, const char* key);
/// The optional parameter "harmonics": 1 when absent; an integer in 1..50 (else std::invalid_argument).
int HarmonicsParameter(const EffectInstance& effect);
/// The model output ŷ; throws std::invalid_argument when DiagnosisSignals::model_output is absent.
const Eigen::VectorXd& NeedModelOutput(const EffectInstance& effect, const DiagnosisSignals& signals);
// The command a command-path effect (EffectTraits::command_path) acts on: the model's drive force in simulation mode
// (DiagnosisSignals::drive_force), else `equation_error` (the logged command, or ŷ). Throws std::invalid_argument
// naming the effect when it is absent.
const Eigen::VectorXd& CommandOf(const EffectInstance& effect, const DiagnosisSignals& signals,
                                 const Eigen::VectorXd& equation_error);
// Simulation mode: the load a command-path effect puts on the plant, `lost`(u) = u − g(u) for the drive's g (a lag, a
// clamp), along the command the loop gives with it: the controller reacts to the load, u = u₀ + h_u ∗ L with u₀ the
// model's drive force and h_u its response to a load (DiagnosisSignals::drive_force_response), so
// L = lost(u₀ + h_u ∗ L), solved from L = lost(u₀) by Anderson-accelerated fixed-point iteration (the closed loop's
// Born series; at most kCommandPathIterations, the iterate with the smallest residual kept). Without h_u: lost(u₀).
// Throws std::invalid_argument naming the effect when the drive force is absent.
inline constexpr int kCommandPathIterations = 12;
Eigen::VectorXd CommandPathLoad(const EffectInstance& effect, const DiagnosisSignals& signals,
                                const std::function<Eigen::VectorXd(const Eigen::VectorXd& command)>& lost);

/// sign(v), 0 inside the dead band |v| ≤ dead_band [m/s].
Eigen::VectorXd SignDeadBand(const Eigen::VectorXd& velocity, double dead_band);

/// The play (backlash) operator: y follows x only once |x − y| reaches half_width, y(0) = x(0) (Krasnosel'skii and
/// Pokrovskii 1989; the far side of a gear or belt play).
Eigen::VectorXd PlayOperator(const Eigen::VectorXd& x, double half_width);

/// The hysteresis term's break-away displacements as proposed, as shares of the record's position span: the smallest
/// 0.5 %, the largest 10 % (effects/hysteresis.cc; the delay-against-hysteresis check, ambiguity_checks.h, refits the
/// same elements).
inline constexpr double kHysteresisMinBreakawayShare = 5e-3, kHysteresisMaxBreakawayShare = 0.1;

/// n values log-spaced from lo to hi, both included (lo alone when n = 1): the break-away displacements of the
/// hysteresis term and of the block that adds it, which must agree. Requires 0 < lo <= hi and n >= 1.
std::vector<double> LogSpaced(double lo, double hi, int n);

/// One column named after the effect.
EffectRegressors SingleColumn(const std::string& effect, Eigen::VectorXd column);

/// Columns g·cos(2πk·z/period), g·sin(2πk·z/period), k = 1..harmonics (N × 2·harmonics), named
/// "<prefix>.cos<k>", "<prefix>.sin<k>"; g = `scale` (N) when given, else 1.
EffectRegressors PeriodicColumns(const Eigen::VectorXd& z, double period, int harmonics, const std::string& prefix,
                                 const Eigen::VectorXd* scale = nullptr);

/// Sets `traits` to re-estimate a position period in the joint fit (EffectTraits::refined_parameter "period"): within
/// ±10 % of the periodogram's peak, which is only as sharp as the travel has cycles (a 40 mm pitch with 4.5 cycles came
/// out at 38.6 mm), and never beyond three cycles in the record's travel, the longest period the proposals name
/// (CatalogueOptions::min_position_cycles_with_harmonics: fewer cannot be told from a smooth function of the position;
/// a loop of 1.9 cycles was walked there by the refit's passes).
void RefinePositionPeriod(EffectTraits* traits);

/// The columns of the generalised force of a mass that varies periodically with the position,
/// M(z) = Σ_k α_k cos(kθ) + β_k sin(kθ), θ = 2πz/period: with the kinetic energy ½M(z)·v², Lagrange's equation
/// d/dt(∂T/∂v) − ∂T/∂z gives M(z)·a + ½M′(z)·v² (Goldstein, Classical Mechanics, 3rd ed., §1.4). Per harmonic k
/// (N × 2·harmonics, named as PeriodicColumns) the column of α_k is a·cos(kθ) − ½(2πk/period)·v²·sin(kθ), that of
/// β_k a·sin(kθ) + ½(2πk/period)·v²·cos(kθ). z [m], v [m/s], a [m/s²] of equal length N; the coefficients in kg.
EffectRegressors InertiaColumns(const Eigen::VectorXd& z, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                                double period, int harmonics, const std::string& prefix);

/// Columns g·ξ^j, ξ = (z − center)/half_range, j = 1..degree (N × degree), named "<prefix>.p<j>"; g = `scale` (N)
/// when given, else 1: a polynomial basis of a smooth function of z over its range, without the constant (the base's
/// level): position_dependent_force, the grammar's smooth factor. Precondition half_range > 0 (the callers'
/// PositiveParameter checks it).
EffectRegressors PowerColumns(const Eigen::VectorXd& z, double center, double half_range, int degree,
                              const std::string& prefix, const Eigen::VectorXd* scale = nullptr);

}  // namespace mb
