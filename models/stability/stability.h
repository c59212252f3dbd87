#pragma once
// Stability analysis of the paper's loop (section 4.2) and the frequency responses of eq. 6, 7 and 12.
//
// Loop (DESIGN.md sign convention): x = P(u + d), u = u_c − d̂_g, u_c = C_FF{x_d} + C_FB{x_d − x} − d̂_d,
// d̂_d = Q∘P_n⁻¹{x} − Q{u_c} (eq. 51), d̂_g = F_gp{α μ(x, F_ẋ{x})} (eq. 53). All controller filters are the
// discrete ones the blocks run (models/stability/dob_design.h), P is the ZOH equivalent of the rigid body
// 1/((M + m_p)s² + Bs) (friction, cogging, quantisation and the resonance are not part of the linear analysis).
//
// The γ terms are l1 norms of discrete impulse responses (Desoer & Vidyasagar): for a sampled loop, ‖·‖₁ is the
// ℓ∞-induced gain, the discrete counterpart of the paper's L1 operator norms.
//
// Two small-gain decompositions are reported:
//  * "paper" (eq. 43–62 as printed): the inner loop is P with C_FB only (Assumption 1, eq. 44–45:
//    G_d→x = S∘P, G_xd→x = T + S∘P∘C_FF), and both d̂_d and d̂_g are fed-back signals bounded by Lemma 1 and 2,
//    with γ_x→u = ‖C_FB‖₁ from u_c = C_FF x_d + C_FB(x_d − x) (eq. 52). ρ = eq. 58, α_max bound = eq. 62.
//    Eq. 54 uses γ_q for both DOB paths although ‖Q‖₁ (dimensionless) and ‖Q∘P_n⁻¹‖₁ [N/m] differ; the
//    dimensionally consistent form ρ' = γ_d→x(γ_q + ‖Q‖₁ γ_x→u + γ_g α K) is reported next to it.
//    Because γ_d→x·‖C_FB‖₁ ≥ ‖T‖₁ ≥ |T(1)| = 1, ρ ≥ 1 for every PD loop: this decomposition can never certify
//    stability of the conventional DOB loop (docs/paper.md).
//  * "dob": the conventional FF/FB/DOB loop closed (eq. 6/7 in discrete form, stable by design) and only the
//    GP path fed back: x = G^DOB_d→x{d − d̂_g} + G^DOB_xd→x{x_d}, so ρ_dob = γ^DOB_d→x·γ_g·α·K and
//    α < 1/(γ^DOB_d→x γ_g K). The same Lemma 2 bound, far less conservative.
// K = L_x + L_ẋ γ_ẋ (eq. 56) needs the GPR's Lipschitz constants (eq. 47); b_μ (Remark 1) its posterior std.
// With the confidence weight (PaperLoop::gp_confidence_weighting, blocks/gpr.h) the GP path is α_max·g·d̂ and K uses
// the Lipschitz constants of g·d̂ (GprModel::ConfidenceWeightedLipschitzConstants, a sampled estimate).
//
// The verdict (StabilityVerdict) answers one question: is the loop, with the diagram's α, certified BIBO stable, and
// up to which α would it be? It uses the "dob" decomposition: the "paper" one certifies nothing more (with a DOB it
// cannot certify at all, see above; without one the two coincide).

#include <complex>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/gpr/gpr_model.h"
#include "models/stability/lti.h"

namespace mb {

/// The linear loop the analysis needs. Plain data; units SI. Finding it in a diagram (by block types or the
/// diagram's "roles") is tools/workflow/loop_from_diagram.h's job; this library knows no diagram.
struct PaperLoop {
  double sample_time = 1e-3;       ///< Ts [s]
  double mass = 0.2621;            ///< true moving mass M + m_p [kg]
  double damping = 3.0;            ///< true linear damping B [N·s/m]
  double nominal_mass = 0.2621;    ///< M_n [kg]
  double nominal_damping = 3.0;    ///< B_n [N·s/m]
  double q_cutoff_hz = 30.0;       ///< Q-filter cut-off [Hz]
  int relative_degree = 2;         ///< n_r
  Discretization q_nominal_inverse_discretization = Discretization::kTustin;
  double kp = 0.0;                 ///< K_p [N/m]
  double kd = 0.0;                 ///< K_d [N·s/m]
  double derivative_cutoff_hz = 300.0;  ///< cut-off of the PD's derivative filter [Hz]
  double velocity_cutoff_hz = 100.0;    ///< F_ẋ cut-off (GP input) [Hz]
  double gp_weight = 0.0;          ///< α_max used for ρ (the f_gp weight)
  bool gp_confidence_weighting = false;  ///< the gpr block scales d̂ by g(x, ẋ): K uses the constants of g·d̂
  double gp_cutoff_hz = 100.0;     ///< F_gp cut-off [Hz]
  int gp_order = 1;                ///< F_gp order
  bool has_dob = true;             ///< false: no DOB (d̂_d = 0; Q and Q∘P_n⁻¹ absent, their γ terms 0)
  bool has_feedforward = true;     ///< false: no C_FF = P_n⁻¹ on the reference (a plain PD loop)
  /// An adaptive mass block (blocks/adaptive_mass_feedforward.h) scaling the command by (M_n + Δm̂)/M_n, Δm̂ clamped
  /// to [adaptive_mass_min, adaptive_mass_max] [kg]: the analysis repeats the "dob" decomposition at both ends.
  bool has_adaptive_mass = false;
  double adaptive_mass_min = 0.0;
  double adaptive_mass_max = 0.0;
};

/// The constants of section 4.2.
struct SmallGainTerms {
  double gamma_d_to_x = 0.0;   ///< γ_d→x = ‖G_d→x‖₁ [m/N]
  double gamma_xd_to_x = 0.0;  ///< γ_xd→x = ‖G_xd→x‖₁
  double gamma_q = 0.0;        ///< γ_q = ‖Q∘P_n⁻¹‖₁ [N/m] (Assumption 2)
  double gamma_q_filter = 1.0; ///< ‖Q‖₁ (dimensionless; 1 for a binomial Q)
  double gamma_x_to_u = 0.0;   ///< γ_x→u [N/m] (eq. 52)
  double gamma_xdot = 0.0;     ///< γ_ẋ = ‖F_ẋ‖₁ [1/s]
  double gamma_g = 1.0;        ///< γ_g = ‖F_gp‖₁
  double lipschitz_x = 0.0;    ///< L_x [N/m] (eq. 47)
  double lipschitz_xdot = 0.0; ///< L_ẋ [N·s/m]
  double alpha_max = 0.0;      ///< α_max of eq. 53
};

/// K = L_x + L_ẋ·γ_ẋ (eq. 56) [N/m].
double LipschitzGain(const SmallGainTerms& t);
/// ρ of eq. 58 as printed: γ_d→x (γ_q (1 + γ_x→u) + γ_g α_max K).
double RhoPaper(const SmallGainTerms& t);
/// ρ' = γ_d→x (γ_q + ‖Q‖₁ γ_x→u + γ_g α_max K): eq. 58 with Lemma 1 written per DOB path.
double RhoConsistent(const SmallGainTerms& t);
/// Eq. 62: α_max < (1/γ_d→x − γ_q (1 + γ_x→u))/(γ_g K). Returns the right-hand side (≤ 0: no α is
/// certified); for K = 0, +∞ if the numerator is positive, else −∞.
double AlphaMaxBoundPaper(const SmallGainTerms& t);
/// Eq. 62 for the "dob" decomposition (γ_q = γ_x→u = 0): 1/(γ_d→x γ_g K).
double AlphaMaxBoundDob(const SmallGainTerms& t);
/// An α bound (eq. 62's right-hand side) in words, never as −∞ or a negative number: "α_max < 4.231";
/// "no α > 0 is certified: ρ ≥ 1 already at α = 0" for a bound ≤ 0 or −∞; for +∞, "any α (K = 0)" when the
/// GPR's constants are known (`has_gpr`), else "not bounded without a GPR model (K unknown)".
std::string AlphaBoundText(double bound, bool has_gpr);

/// One frequency point of eq. 6, 7 and 12, continuous (the paper's formulas at s = jω) and for the sampled loop
/// (z = e^{jωTs}, the blocks' discrete filters, ZOH plant; C_FF = P_n⁻¹(jω)·e^{jωTs/2} because the feedforward
/// comes from the reference's exact derivatives sampled mid-interval, `time_advance` = Ts/2 in the diagrams).
/// G_d→x includes P (eq. 44: S∘P; eq. 7 as printed omits it).
struct BodePoint {
  double frequency_hz = 0.0;
  std::complex<double> xd_to_x_continuous, d_to_x_continuous, d_to_dhat_continuous;
  std::complex<double> xd_to_x_discrete, d_to_x_discrete, d_to_dhat_discrete;
};

/// Bode data at `frequencies_hz` (each 0 < f < 1/(2Ts)). @throws std::invalid_argument for a frequency outside.
std::vector<BodePoint> ClosedLoopBode(const PaperLoop& loop, const std::vector<double>& frequencies_hz);
/// `count` log-spaced frequencies from `min_hz` to 0.99·Nyquist.
std::vector<double> LogFrequencies(double min_hz, double sample_time, int count);

/// Impulse responses of the sampled loop (first `count` samples), for checks and plots.
enum class LoopPath { kDisturbanceToPosition, kReferenceToPosition };
Eigen::VectorXd LoopImpulseResponse(const PaperLoop& loop, LoopPath path, bool with_dob, int count);

struct StabilityOptions {
  double beta_delta = 2.0;      ///< β_δ of Remark 1 (eq. 49–50)
  int impulse_samples = 20000;  ///< length of the closed-loop impulse responses (20 s at 1 ms)
  int bode_points = 200;
  double bode_min_hz = 0.1;
  int lipschitz_grid = 8192;
  int weighted_lipschitz_grid = 256;  ///< per axis, for the confidence-weighted mean (O(M²) per point)
  int std_grid = 64;
};

/// The condition a verdict fails, in the order they are checked.
enum class StabilityCondition {
  kNone,                    ///< none: certified
  kLoopStable,              ///< the conventional FF/FB/DOB loop (GP path open) is stable
  kAdaptiveMassLoopStable,  ///< that loop stays stable at both ends of the adaptive mass's clamp
  kGprModelGiven,           ///< α > 0 needs the GPR model's Lipschitz constants (K) to be bounded
  kSmallGain,               ///< ρ_dob < 1 at the diagram's α (and at both ends of an adaptive mass's clamp)
};

/// "loop_stable", "adaptive_mass_loop_stable", "gpr_model_given", "small_gain" ("" for kNone): the JSON names.
const char* ToString(StabilityCondition condition);

/// The one-line answer of the analysis ("dob" decomposition).
struct StabilityVerdict {
  bool certified = false;
  StabilityCondition failing_condition = StabilityCondition::kNone;
  std::string reason;  ///< why it fails or holds, in words with the numbers ("ρ = 13.61 ≥ 1 at α = 0.9")
  double alpha_used = 0.0;  ///< the diagram's α (f_gp weight)
  /// The largest certified α (strict: α < alpha_max certifies): ≥ 0, 0 when no α ≥ 0 is certified (the loop is
  /// unstable), +∞ when any α is (K = 0), NaN when unknown (no GPR model). Never negative.
  double alpha_max = std::numeric_limits<double>::quiet_NaN();
  std::string line;  ///< "certified: …" or "NOT certified: …": reason and the largest α, one line
};

struct StabilityReport {
  PaperLoop loop;
  bool inner_loop_stable = false;  ///< P with C_FB (Assumption 1)
  bool dob_loop_stable = false;    ///< the conventional FF/FB/DOB loop
  SmallGainTerms paper;            ///< "paper" decomposition
  SmallGainTerms dob;              ///< "dob" decomposition (gamma_q, gamma_x_to_u = 0)
  bool has_gpr = false;
  double b_mu = 0.0;               ///< Remark 1, eq. 50 [N] (0 without a GPR)
  double rho_paper = std::numeric_limits<double>::quiet_NaN();        ///< eq. 58
  double rho_consistent = std::numeric_limits<double>::quiet_NaN();   ///< eq. 58, per-path Lemma 1
  double alpha_max_bound_paper = std::numeric_limits<double>::quiet_NaN();  ///< eq. 62
  double rho_dob = std::numeric_limits<double>::quiet_NaN();
  double alpha_max_bound_dob = std::numeric_limits<double>::quiet_NaN();
  /// With an adaptive mass: the "dob" decomposition with Δm̂ frozen at each end of its clamp {min, max}: the loop is
  /// the designed one on a plant of mass M·s and damping B·s, s = M_n/(M_n + Δm̂), and the GP force enters it scaled
  /// by s, so γ_d→x = s·‖G_d→x‖₁ of that loop. Stable flags and ρ_dob at each end (NaN if unstable).
  bool adaptive_mass_loop_stable[2] = {true, true};
  double adaptive_mass_rho_dob[2] = {std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::quiet_NaN()};
  /// With an adaptive mass: the "dob" α bound 1/(γ_d→x γ_g K) at each end of the clamp (NaN if unstable).
  double adaptive_mass_alpha_max_bound_dob[2] = {std::numeric_limits<double>::quiet_NaN(),
                                                 std::numeric_limits<double>::quiet_NaN()};
  StabilityVerdict verdict;
  std::vector<BodePoint> bode;
  std::vector<std::string> notes;  ///< plain-language verdicts and caveats
};

/// Runs the analysis. Without a GPR model, K = 0 (no GP path): ρ reduces to the DOB term and the α bounds are
/// +∞ where their numerator is positive. @throws std::invalid_argument for an invalid loop (bad filter
/// parameters).
StabilityReport AnalyseStability(const PaperLoop& loop, const GprModel* gpr = nullptr,
                                 const StabilityOptions& options = {});

/// Everything as JSON (numbers in SI; complex responses as magnitude and phase in degrees; +∞ as null with a
/// note). Per decomposition, "alpha_used" is the diagram's α and "alpha_max_bound" eq. 62's bound clipped at 0 (0: no
/// α > 0 is certified; null: +∞). "verdict": {"certified", "failing_condition" (ToString, null when certified),
/// "reason", "alpha_used", "alpha_max" (null when +∞ or unknown, see "alpha_max_text"), "alpha_max_text", "line"}.
nlohmann::json ToJson(const StabilityReport& report);

}  // namespace mb
