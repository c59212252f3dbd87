#include "tests/diagnosis/independent_plant.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

namespace mb::independent {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The truth (not the user's diagram: M 100, Fv 200, Fc 20 there, sign(v) friction).
constexpr double kMass = 94.0, kViscous = 195.0, kCoulomb = 21.0, kCoulombVelocity = 5e-4, kOffset = -0.5;
constexpr double kPayload = 12.0;
constexpr double kStribeckExtra = 9.0, kStribeckVelocity = 0.01;
constexpr double kDelay = 0.004;
constexpr double kVibrationAmplitude = 2.0, kVibrationHz = 9.0;
constexpr double kLoadMass = 6.0, kLoadHz = 31.7, kLoadDamping = 0.02;
constexpr double kSpringCentre = 0.1, kSpringLinear = 30.0, kSpringCubic = 3000.0;
constexpr double kLoadFriction = 4.0, kPlayHalfWidth = 5e-4;
constexpr double kDriftAmplitude = 2.0;  // [N], kDriftingVibration
constexpr double kGearLoadMass = 25.0, kGearHz = 18.0, kGearDamping = 0.15, kGearBearing = 15.0;  // kLoadBehindPlay
constexpr double kSubStep = 1e-4;  // plant integration [s]
constexpr double kBoucWenForce = 6.0, kBoucWenDisplacement = 3e-3;  // [N], z₀ [m]
constexpr double kActuatorLag = 0.004;
constexpr double kVelocityEstimateHz = 200.0;  // the controller's velocity estimate's first-order low-pass [Hz]
constexpr double kHumAmplitude = 1.5, kHumHz = 50.0;
constexpr double kShortStrokePeriod = 0.025;  // 7.2 cycles in the 0.18 m travel
constexpr double kUpperLimit = 120.0, kLowerLimit = -135.0;
constexpr double kGravityTorque = 7.5, kGravityPhase = 0.4;  // [N·m], [rad]
constexpr double kPitchFrictionAmplitude = 2.5, kPitchFrictionPeriod = 0.008;  // [N], [m]
constexpr double kShortPitchAmplitude = 4.0, kShortPitchPeriod = 0.03;        // [N], [m]: 6 cycles in 0.18 m
constexpr double kRippleDepth = 0.03, kForceRipplePeriod = 0.012;             // [-], [m]
constexpr double kSpotFriction = 6.0, kSpotStart = 0.12, kSpotEnd = 0.13;     // [N], [m], [m]
constexpr double kCoupledMass = 4.0;                                          // [kg]
constexpr double kPreloadFriction = 5.0, kPreloadMiddle = 0.13, kPreloadSpread = 0.04;  // [N], [m], [m]
constexpr double kBellowsDamping = 80.0, kBellowsCentre = 0.055, kBellowsSpread = 0.01;  // [N·s/m], [m], [m]
constexpr double kLinkageMass = 5.0, kLinkagePeriod = 0.04, kLinkagePhase = 0.7;  // [kg], [m], [rad]
// The dashpot: oil density [kg/m³], the orifice's discharge coefficient, the piston's and the orifice's areas [m²].
constexpr double kOilDensity = 860.0, kDischargeCoefficient = 0.6, kPistonArea = 1e-3, kOrificeArea = 5e-5;
// A cold start: the grease's temperature rise [K], its thermal time constant [s], the viscosity's temperature
// coefficient [1/K] (Reynolds' law μ = μ₀·exp(−β·Δθ)).
constexpr double kGreaseRise = 9.0, kThermalTimeConstant = 3.5, kViscosityCoefficient = 0.03;
// The voltage-limited drive: winding resistance [Ω] and inductance [H], force constant [N/A], back-EMF constant
// [V·s/m], bus voltage [V]; the current loop's bandwidth [rad/s] and its update period [s].
constexpr double kWindingResistance = 4.0, kWindingInductance = 2e-3, kForceConstant = 30.0, kBackEmfConstant = 30.0;
constexpr double kBusVoltage = 20.0;
constexpr double kCurrentBandwidth = 2.0 * std::numbers::pi * 3000.0, kCurrentPeriod = 1e-5;
// Its steady-state force limits: ±k_t·V_bus/R at standstill, falling by k_t·k_e/R per m/s in the direction of motion.
constexpr double kStallForce = kForceConstant * kBusVoltage / kWindingResistance;                 // 150 N
constexpr double kEmfSlope = kForceConstant * kBackEmfConstant / kWindingResistance;              // 225 N·s/m

// The other axis's acceleration [m/s²]: bursts of a 3.1 Hz oscillation under a 0.7 Hz envelope.
double OtherAxisAcceleration(double t) {
  return 2.0 * std::sin(kTwoPi * 0.7 * t) * std::sin(kTwoPi * 3.1 * t);
}

// Its velocity [m/s], from rest: 2·sin(2π·0.7t)·sin(2π·3.1t) = cos(2π·2.4t) − cos(2π·3.8t), integrated.
double OtherAxisVelocity(double t) {
  return std::sin(kTwoPi * 2.4 * t) / (kTwoPi * 2.4) - std::sin(kTwoPi * 3.8 * t) / (kTwoPi * 3.8);
}

// A hall temperature [°C] that drifts slowly and does not act on the axis.
double HallTemperature(double t) { return 22.0 + 1.5 * std::sin(kTwoPi * t / 40.0) + 0.2 * std::sin(kTwoPi * t / 3.0); }

// The force constant's ripple: the drive applies u·(1 + δ(x)).
double ForceConstantRipple(double x) { return kRippleDepth * std::sin(kTwoPi * x / kForceRipplePeriod + 1.0); }

// The weak magnet: its width and centre [m], the share of its remanence lost, the coil's length [m].
constexpr double kWeakMagnetWidth = 0.011, kWeakMagnetCentre = 0.092, kWeakness = 0.25, kCoilLength = 0.034;

// The force constant's fraction lost at coil position x: the lost flux of the part of the weak magnet under the coil.
double WeakMagnetLoss(double x) {
  const double lo = std::max(x - 0.5 * kCoilLength, kWeakMagnetCentre - 0.5 * kWeakMagnetWidth);
  const double hi = std::min(x + 0.5 * kCoilLength, kWeakMagnetCentre + 0.5 * kWeakMagnetWidth);
  return kWeakness * std::max(hi - lo, 0.0) / kCoilLength;
}

// The tilted magnet track: the air gap [m] along the travel, the magnets' thickness [m] and recoil permeability.
constexpr double kGapNear = 6e-4, kGapFar = 1.4e-3, kTrackStart = 0.01, kTrackEnd = 0.19;
constexpr double kMagnetThickness = 4e-3, kRecoilPermeability = 1.05;

// The force constant at x over the one at the travel's middle: the gap's flux density h_m/(h_m + μ_r·g(x)).
double AirGapScale(double x) {
  const auto gap = [](double p) {
    return kGapNear + (kGapFar - kGapNear) * (p - kTrackStart) / (kTrackEnd - kTrackStart);
  };
  const auto flux = [](double g) { return kMagnetThickness / (kMagnetThickness + kRecoilPermeability * g); };
  return flux(gap(x)) / flux(gap(0.5 * (kTrackStart + kTrackEnd)));
}

// The ferrite magnets' temperature [°C] and the remanence's temperature coefficient [1/K] about its 50 °C mean.
constexpr double kMagnetMeanTemperature = 50.0, kRemanenceCoefficient = -0.002;
double MagnetTemperature(double t) {
  return kMagnetMeanTemperature + 12.0 * std::sin(kTwoPi * t / 11.0) + 4.0 * std::sin(kTwoPi * t / 3.1 + 0.5);
}

// What the drive makes of a force command at (t, x): the force constant's share of its nominal value.
double ForceConstantScale(Hidden h, double t, double x) {
  if (h == Hidden::kWeakMagnet) return 1.0 - WeakMagnetLoss(x);
  if (h == Hidden::kAirGap) return AirGapScale(x);
  if (h == Hidden::kMagnetTemperature) {
    return 1.0 + kRemanenceCoefficient * (MagnetTemperature(t) - kMagnetMeanTemperature);
  }
  return 1.0;
}

// The grease's temperature above its cold start [K]: the coils' constant heat through a first-order thermal lag.
double GreaseWarming(double t) { return kGreaseRise * -std::expm1(-std::max(t, 0.0) / kThermalTimeConstant); }

// The viscous coefficient of the warming grease [N·s/m]: the viscosity's exponential fall with temperature.
double WarmViscous(double t) { return kViscous * std::exp(-kViscosityCoefficient * GreaseWarming(t)); }

// The linkage's share of the moving mass [kg] and its slope along the travel [kg/m].
double LinkageMass(double x) { return kLinkageMass * std::sin(kTwoPi * x / kLinkagePeriod + kLinkagePhase); }
double LinkageMassSlope(double x) {
  return kLinkageMass * kTwoPi / kLinkagePeriod * std::cos(kTwoPi * x / kLinkagePeriod + kLinkagePhase);
}

bool Has(Hidden h, Hidden what) {
  return h == what || (h == Hidden::kRippleAndDelay && (what == Hidden::kPositionRipple || what == Hidden::kDelay)) ||
         (h == Hidden::kRotaryHysteresis && what == Hidden::kHysteresis) ||
         (h == Hidden::kRotaryDriftingVibration && what == Hidden::kDriftingVibration) ||
         (h == Hidden::kRotaryLoadBehindPlay && what == Hidden::kLoadBehindPlay);
}

constexpr double kPayloadStep = 31.0, kPayloadStepTime = 8.0;
constexpr double kViscousDrift = -50.0, kDriftSpan = 16.0;  // [N·s/m] over [s]

double Mass(Hidden h, double t) {
  return kMass + (Has(h, Hidden::kPayload) ? kPayload : 0.0) +
         (Has(h, Hidden::kPayloadStep) && t >= kPayloadStepTime ? kPayloadStep : 0.0);
}

// Friction law: viscous + tanh-regularised Coulomb (+ Stribeck), resisting +v.
double FrictionLaw(Hidden h, double v) {
  const double s = std::tanh(v / kCoulombVelocity);
  double f = kViscous * v + kCoulomb * s;
  if (Has(h, Hidden::kStribeck)) f += kStribeckExtra * std::exp(-(v / kStribeckVelocity) * (v / kStribeckVelocity)) * s;
  return f;
}

constexpr double kDampingRippleCoefficient = 40.0, kDampingRipplePeriod = 0.015;  // [N·s/m], [m]
constexpr double kViscosityPerKelvin = -8.0, kOilReference = 30.0;      // [N·s/m/K], [°C]

// The oil temperature [°C]: the machine's duty cycle heats and cools it around 30 °C (periods 7 s and 2.3 s).
double OilTemperature(double t) {
  return kOilReference + 3.0 * std::sin(kTwoPi * t / 7.0) + 1.2 * std::sin(kTwoPi * t / 2.3 + 1.0);
}

// The dashpot's force [N] at carriage velocity v: the pressure drop across the orifice on the piston, against v.
double OrificeDrag(double v) {
  const double flow = kPistonArea * v;                               // [m³/s]
  const double jet = flow / (kDischargeCoefficient * kOrificeArea);  // [m/s] through the orifice's vena contracta
  return 0.5 * kOilDensity * jet * std::abs(jet) * kPistonArea;
}

// The hidden force of (x, v, t) resisting the motion (what the motor must add), without states.
double StatelessHidden(Hidden h, double t, double x, double v) {
  double f = 0.0;
  if (Has(h, Hidden::kPositionRipple)) {
    f += 1.5 * std::sin(kTwoPi * x / 0.006 + 0.3) + 0.4 * std::sin(2.0 * kTwoPi * x / 0.006);
  }
  if (Has(h, Hidden::kSpeedRipple)) f += 15.0 * std::abs(v) * std::sin(kTwoPi * x / 0.005);
  if (Has(h, Hidden::kFrictionDrift)) f += kViscousDrift * std::min(t / kDriftSpan, 1.0) * v;
  if (Has(h, Hidden::kWarmUp)) f += (WarmViscous(t) - kViscous) * v;
  if (Has(h, Hidden::kShortStroke)) f += 15.0 * std::abs(v) * std::sin(kTwoPi * x / kShortStrokePeriod);
  if (Has(h, Hidden::kVibration)) f -= kVibrationAmplitude * std::sin(kTwoPi * kVibrationHz * t + 0.7);
  if (Has(h, Hidden::kDriftingVibration)) {  // the phase is the integral of f(t) = f₀ + ḟ·t
    f -= kDriftAmplitude * std::sin(kTwoPi * (kDriftStartHz * t + 0.5 * kDriftRate * t * t) + 0.4);
  }
  if (Has(h, Hidden::kPositionForce)) {
    const double d = x - kSpringCentre;
    f += kSpringLinear * d + kSpringCubic * d * d * d;
  }
  const double slip = std::tanh(v / kCoulombVelocity);
  if (Has(h, Hidden::kPitchFriction)) {
    f += kPitchFrictionAmplitude * std::sin(kTwoPi * x / kPitchFrictionPeriod + 0.5) * slip;
  }
  if (Has(h, Hidden::kShortPitchFriction)) f += kShortPitchAmplitude * std::sin(kTwoPi * x / kShortPitchPeriod + 1.1) * slip;
  if (Has(h, Hidden::kLocalFriction) && x >= kSpotStart && x <= kSpotEnd) f += kSpotFriction * slip;
  if (Has(h, Hidden::kLocalDamping)) {
    const double z = (x - kBellowsCentre) / kBellowsSpread;
    f += kBellowsDamping * std::exp(-z * z) * v;
  }
  if (Has(h, Hidden::kFrictionAlongTravel)) {
    f += kPreloadFriction * 0.5 * (1.0 + std::tanh((x - kPreloadMiddle) / kPreloadSpread)) * slip;
  }
  if (Has(h, Hidden::kCoupledAxis) || Has(h, Hidden::kCoupledAxisVelocity)) {
    f += kCoupledMass * OtherAxisAcceleration(t);
  }
  if (Has(h, Hidden::kDampingRipple)) f += kDampingRippleCoefficient * v * std::sin(kTwoPi * x / kDampingRipplePeriod + 0.3);
  if (Has(h, Hidden::kOilTemperature)) f += kViscosityPerKelvin * (OilTemperature(t) - kOilReference) * v;
  if (Has(h, Hidden::kOrificeDrag)) f += OrificeDrag(v);
  if (Has(h, Hidden::kGravity)) {  // the arm's torque as a force on the carriage: τ·dθ/dx
    f += kRadPerMetre * kGravityTorque * std::sin(kRadPerMetre * (x - 0.1) + kGravityPhase);
  }
  return f;
}

// The Bouc–Wen element's z [m] after a displacement dx (kHysteresis): dz = dx − β|dx|z − γ·dx|z|, β = γ = 1/(2z₀),
// in steps no longer than z₀/200 (explicit Euler along the displacement: the model is rate-independent).
double BoucWen(double z, double dx) {
  const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(dx) / (kBoucWenDisplacement / 200.0))));
  const double h = dx / steps, beta = 0.5 / kBoucWenDisplacement;
  for (int i = 0; i < steps; ++i) z += h - beta * std::abs(h) * z - beta * h * std::abs(z);
  return z;
}

double BoucWenForce(double z) { return kBoucWenForce * z / kBoucWenDisplacement; }

// The play operator: the far side of a ±half-width play follows x once the play is taken up.
double Play(double x, double previous) { return std::clamp(previous, x - kPlayHalfWidth, x + kPlayHalfWidth); }

// The load's friction through the play: felt while the play is taken up (and the load slides).
double BacklashForce(double x, double far_side, double v) {
  const bool engaged = std::abs(x - far_side) >= kPlayHalfWidth * (1.0 - 1e-9);
  return engaged ? kLoadFriction * std::tanh(v / kCoulombVelocity) : 0.0;
}

// The resonant load's spring–damper force on the carriage.
struct Load {
  double k = kLoadMass * (kTwoPi * kLoadHz) * (kTwoPi * kLoadHz);
  double c = 2.0 * kLoadDamping * kLoadMass * kTwoPi * kLoadHz;
  double Force(double x, double v, double xl, double vl) const { return k * (x - xl) + c * (v - vl); }
};

// The gearbox shaft's force on the load (kLoadBehindPlay) [N]: nothing while the twist x − x_L is inside the play, a
// spring on the twist beyond it and a damper on the twist rate while in contact.
double GearShaftForce(double x, double v, double xl, double vl) {
  const double twist = x - xl, w = kTwoPi * kGearHz;
  if (std::abs(twist) <= kGearHalfGap) return 0.0;
  const double k = kGearLoadMass * w * w, c = 2.0 * kGearDamping * kGearLoadMass * w;
  return k * (twist - std::copysign(kGearHalfGap, twist)) + c * (v - vl);
}

// A jerk-limited point-to-point reference on the fine grid kSubStep, with dwell between moves. The equation-error
// records' controller reads it held from the grid point below, and t/kSubStep at a controller instant k·1 ms rounds
// down on one in six of them (29.999… → 29): it then reads the reference 0.1 ms stale, a kick of kp·v·0.1 ms (up to
// 12 N) at random steps, which their logged force carries and so any model of the force sees. A record with its
// reference logged (simulation mode) is compared with a diagram whose controller reads the logged reference between
// its samples, which holds no such kick: there the reference is `continuous`, read between its grid points by linear
// interpolation, the same whenever the controller or the logger reads it.
struct Reference {
  std::vector<double> x, v, a;
  bool continuous = false;
  void At(double t, double* xr, double* vr, double* ar) const {
    if (!continuous) {
      const auto i = std::min(x.size() - 1, static_cast<std::size_t>(std::max(0.0, t / kSubStep)));
      *xr = x[i]; *vr = v[i]; *ar = a[i];
      return;
    }
    const double q = std::clamp(t / kSubStep, 0.0, static_cast<double>(x.size() - 1));
    const auto i = std::min(x.size() - 2, static_cast<std::size_t>(q));
    const double w = q - static_cast<double>(i);
    *xr = x[i] + w * (x[i + 1] - x[i]);
    *vr = v[i] + w * (v[i + 1] - v[i]);
    *ar = a[i] + w * (a[i + 1] - a[i]);
  }
};

Reference MakeReference(double duration, std::mt19937* rng) {
  const double accel = 1.5, jerk_time = 0.02;
  std::uniform_real_distribution<double> target(0.01, 0.19), speed(0.04, 0.2), dwell(0.2, 0.6);
  Reference r;
  const auto n = static_cast<std::size_t>(duration / kSubStep) + 2;
  double x = 0.1, v = 0.0;
  std::vector<double> profile;  // acceleration of the next move on the fine grid
  std::size_t next = 0;
  double rest_until = 0.3;
  while (r.a.size() < n) {
    const double t = static_cast<double>(r.a.size()) * kSubStep;
    if (next >= profile.size() && t >= rest_until) {  // plan a move
      double goal = target(*rng);
      while (std::abs(goal - x) < 0.03) goal = target(*rng);
      const double distance = std::abs(goal - x), sign = goal > x ? 1.0 : -1.0;
      double top = speed(*rng);
      if (top * (top / accel + jerk_time) > distance) {
        top = accel * (-jerk_time + std::sqrt(jerk_time * jerk_time + 4.0 * distance / accel)) / 2.0;
      }
      const double ramp = top / accel + jerk_time;  // duration of the acceleration phase
      const double coast = (distance - top * ramp) / top;
      auto phase = [&](double q) {  // trapezoidal acceleration over [0, ramp]
        return accel * std::min({1.0, q / jerk_time, (ramp - q) / jerk_time, 1.0});
      };
      profile.clear();
      for (double q = 0.0; q < 2.0 * ramp + coast; q += kSubStep) {
        double a = 0.0;
        if (q < ramp) a = phase(q);
        else if (q >= ramp + coast) a = -phase(q - ramp - coast);
        profile.push_back(sign * std::max(-accel, std::min(accel, a)));
      }
      next = 0;
      rest_until = t + static_cast<double>(profile.size()) * kSubStep + dwell(*rng);
    }
    double a = 0.0;
    if (next < profile.size()) a = profile[next++];
    else v = 0.0;
    r.a.push_back(a);
    r.v.push_back(v);
    r.x.push_back(x);
    x += kSubStep * v + 0.5 * kSubStep * kSubStep * a;
    v += kSubStep * a;
  }
  return r;
}

// The drive's winding and its current loop: a PI on the current error with pole–zero cancellation (K_p = L·ω_c,
// K_i = R·ω_c), updated every kCurrentPeriod, its voltage clamped at ±V_bus (integration stops while clamped), the
// winding L·di/dt = V − R·i − k_e·v solved exactly over each update (v held).
class Winding {
 public:
  /// The mean current [A] over the next `dt` [s] for the reference `reference` [A] at the carriage speed v [m/s].
  double Advance(double reference, double v, double dt) {
    const int steps = std::max(1, static_cast<int>(std::lround(dt / kCurrentPeriod)));
    const double h = dt / steps, decay = std::exp(-kWindingResistance * h / kWindingInductance);
    double charge = 0.0;
    for (int k = 0; k < steps; ++k) {
      const double error = reference - current_;
      const double wanted = kWindingInductance * kCurrentBandwidth * error +
                            kWindingResistance * kCurrentBandwidth * integral_;
      const double voltage = std::clamp(wanted, -kBusVoltage, kBusVoltage);
      if (voltage == wanted) integral_ += error * h;
      const double settled = (voltage - kBackEmfConstant * v) / kWindingResistance;
      charge += settled * h + (current_ - settled) * (1.0 - decay) * kWindingInductance / kWindingResistance;
      current_ = settled + (current_ - settled) * decay;
    }
    return charge / dt;
  }

 private:
  double current_ = 0.0, integral_ = 0.0;
};

// The plant's state: carriage, resonant load, the play's far side.
struct State {
  double x = 0.1, v = 0.0, xl = 0.1, vl = 0.0, far = 0.1;
  double z = 0.0;  // kHysteresis: the Bouc–Wen element [m]
  Winding winding;  // kBackEmf
};

// ẋ of (x, v, xl, vl) under the force u at time t.
std::array<double, 4> Derivative(Hidden h, double t, const std::array<double, 4>& s, double far, double z,
                                 double u) {
  double resist = FrictionLaw(h, s[1]) + kOffset + StatelessHidden(h, t, s[0], s[1]);
  if (Has(h, Hidden::kHysteresis)) resist += BoucWenForce(z);
  std::array<double, 4> d{s[1], 0.0, 0.0, 0.0};
  if (Has(h, Hidden::kResonance)) {
    const double fl = Load{}.Force(s[0], s[1], s[2], s[3]);
    resist += fl;
    d[2] = s[3];
    d[3] = fl / kLoadMass;
  }
  if (Has(h, Hidden::kLoadBehindPlay)) {
    const double fl = GearShaftForce(s[0], s[1], s[2], s[3]);
    resist += fl;
    d[2] = s[3];
    d[3] = (fl - kGearBearing * s[3]) / kGearLoadMass;
  }
  if (Has(h, Hidden::kBacklash)) resist += BacklashForce(s[0], Play(s[0], far), s[1]);
  double mass = Mass(h, t);
  if (Has(h, Hidden::kInertiaRipple)) {  // d/dt(M(x)·v) − ½M′(x)·v² = F: M(x)·a = F − ½M′(x)·v²
    mass += LinkageMass(s[0]);
    resist += 0.5 * LinkageMassSlope(s[0]) * s[1] * s[1];
  }
  d[1] = (u - resist) / mass;
  return d;
}

void Advance(Hidden h, double t0, double dt, double u, State* st) {
  const int steps = std::max(1, static_cast<int>(std::ceil(dt / kSubStep - 1e-9)));
  const double hstep = dt / steps;
  std::array<double, 4> s{st->x, st->v, st->xl, st->vl};
  for (int i = 0; i < steps; ++i) {
    const double t = t0 + i * hstep;
    // The voltage-limited drive turns the force command into the winding's mean current over the sub-step.
    const double force =
        Has(h, Hidden::kBackEmf) ? kForceConstant * st->winding.Advance(u / kForceConstant, s[1], hstep) : u;
    auto add = [](const std::array<double, 4>& a, const std::array<double, 4>& b, double f) {
      return std::array<double, 4>{a[0] + f * b[0], a[1] + f * b[1], a[2] + f * b[2], a[3] + f * b[3]};
    };
    const auto k1 = Derivative(h, t, s, st->far, st->z, force);
    const auto k2 = Derivative(h, t + hstep / 2, add(s, k1, hstep / 2), st->far, st->z, force);
    const auto k3 = Derivative(h, t + hstep / 2, add(s, k2, hstep / 2), st->far, st->z, force);
    const auto k4 = Derivative(h, t + hstep, add(s, k3, hstep), st->far, st->z, force);
    const double x_before = s[0];
    for (std::size_t j = 0; j < 4; ++j) s[j] += hstep / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    st->far = Play(s[0], st->far);
    if (Has(h, Hidden::kHysteresis)) st->z = BoucWen(st->z, s[0] - x_before);
  }
  st->x = s[0]; st->v = s[1]; st->xl = s[2]; st->vl = s[3];
}

// PID on the encoder with feedforward (an imperfect guess of the mass and friction), integral action that stops
// while the force is clipped, and the velocity from a first-order-filtered difference.
class Controller {
 public:
  double Update(double t, double x_measured, const Reference& ref) {
    double xr = 0.0, vr = 0.0, ar = 0.0;
    ref.At(t, &xr, &vr, &ar);
    const double dt = started_ ? t - t_prev_ : 1e-3;
    const double raw_v = started_ ? (x_measured - x_prev_) / dt : 0.0;
    const double alpha = dt / (dt + 1.0 / (kTwoPi * kVelocityEstimateHz));
    v_est_ += alpha * (raw_v - v_est_);
    started_ = true;
    t_prev_ = t;
    x_prev_ = x_measured;
    const double e = xr - x_measured;
    const double w = kTwoPi * 15.0;
    const double kp = kMass * w * w, kd = 2.0 * 0.7 * w * kMass, ki = kp * w / 8.0;
    const double feedforward = 90.0 * ar + 180.0 * vr + 18.0 * std::tanh(vr / 1e-3);
    double u = kp * e + ki * integral_ + kd * (vr - v_est_) + feedforward;
    const double limit = 400.0;
    if (std::abs(u) < limit) integral_ += e * dt;
    u = std::clamp(u, -limit, limit);
    return u;
  }

 private:
  bool started_ = false;
  double t_prev_ = 0.0, x_prev_ = 0.0, v_est_ = 0.0, integral_ = 0.0;
};

}  // namespace

CaseSpec Case(std::string name, Hidden hidden, std::string effect, std::string parameter, double truth,
              double tolerance) {
  CaseSpec c;
  c.name = std::move(name);
  c.hidden = hidden;
  c.effect = std::move(effect);
  c.parameter = std::move(parameter);
  c.truth = truth;
  c.tolerance = tolerance;
  return c;
}

std::vector<CaseSpec> Cases() {
  std::vector<CaseSpec> c;
  c.push_back(Case("position ripple", Hidden::kPositionRipple, "position_periodic", "period", 0.006, 0.03));
  c.push_back(Case("speed-dependent ripple", Hidden::kSpeedRipple, "velocity_dependent_ripple", "period", 0.005, 0.03));
  CaseSpec stribeck = Case("Stribeck", Hidden::kStribeck, "stribeck_friction", "stribeck_velocity", kStribeckVelocity,
                           0.15);
  stribeck.law = true;
  c.push_back(stribeck);
  c.push_back(Case("delay", Hidden::kDelay, "time_delay", "delay", kDelay, 0.15));
  c.push_back(Case("vibration (decoy)", Hidden::kVibration, "time_periodic", "frequency_hz", kVibrationHz, 0.03));
  c.push_back(Case("resonance", Hidden::kResonance, "resonance", "frequency_hz", kLoadHz, 0.03));
  c.push_back(Case("position-dependent force", Hidden::kPositionForce, "position_dependent_force", "", 0.0, 0.0));
  c.push_back(Case("backlash", Hidden::kBacklash, "backlash", "backlash", 2.0 * kPlayHalfWidth, 0.15));
  CaseSpec payload = Case("payload", Hidden::kPayload, "mass_mismatch", "", 0.0, 0.0);
  payload.mass_known = true;
  c.push_back(payload);
  CaseSpec two = Case("ripple + delay", Hidden::kRippleAndDelay, "position_periodic", "period", 0.006, 0.03);
  two.second_effect = "time_delay";
  c.push_back(two);
  c.push_back(Case("actuator lag", Hidden::kActuatorLag, "actuator_lag", "lag", kActuatorLag, 0.15));
  c.push_back(Case("drive saturation", Hidden::kSaturation, "drive_saturation", "upper_limit", kUpperLimit, 0.10));
  c.push_back(Case("short stroke", Hidden::kShortStroke, "velocity_dependent_ripple", "period", kShortStrokePeriod,
                   0.03));
  c.push_back(Case("payload step", Hidden::kPayloadStep, "mass_change", "change_time", kPayloadStepTime, 0.0625));
  c.push_back(Case("rotary gravity", Hidden::kGravity, "gravity", "amplitude", kGravityTorque, 0.05));
  c.push_back(Case("mains hum", Hidden::kMainsHum, "time_periodic", "frequency_hz", kHumHz, 0.03));
  c.push_back(Case("friction drift", Hidden::kFrictionDrift, "friction_drift", "change", kViscousDrift, 0.10));
  c.push_back(Case("friction along the pitch", Hidden::kPitchFriction, "friction_ripple", "period",
                   kPitchFrictionPeriod, 0.03));
  c.push_back(Case("pitch friction, 6 cycles", Hidden::kShortPitchFriction, "friction_ripple", "period",
                   kShortPitchPeriod, 0.03));
  c.push_back(Case("force-constant ripple", Hidden::kForceRipple, "force_constant_ripple", "period", kForceRipplePeriod,
                   0.03));
  c.push_back(Case("friction at one spot", Hidden::kLocalFriction, "local_friction", "center",
                   0.5 * (kSpotStart + kSpotEnd), 0.05));
  c.push_back(Case("coupled axis (extra column)", Hidden::kCoupledAxis, "logged_column", "", 0.0, 0.0));
  c.push_back(Case("idle extra column", Hidden::kIdleColumn, "", "", 0.0, 0.0));
  c.push_back(Case("damping along the pitch", Hidden::kDampingRipple, "damping_ripple", "period",
                   kDampingRipplePeriod, 0.03));
  c.push_back(Case("viscosity follows oil temperature", Hidden::kOilTemperature, "column_damping", "", 0.0, 0.0));
  c.push_back(Case("friction along the travel", Hidden::kFrictionAlongTravel, "friction_along_travel", "", 0.0, 0.0));
  c.push_back(Case("damping at one stretch", Hidden::kLocalDamping, "local_damping", "center", kBellowsCentre, 0.05));
  c.push_back(Case("coupled axis (its velocity logged)", Hidden::kCoupledAxisVelocity, "logged_column_rate", "", 0.0,
                   0.0));
  c.push_back(Case("mass along the travel (a linkage)", Hidden::kInertiaRipple, "inertia_ripple", "period",
                   kLinkagePeriod, 0.03));
  c.push_back(Case("dashpot orifice drag", Hidden::kOrificeDrag, "quadratic_drag", "drag_coefficient",
                   0.5 * kOilDensity * kPistonArea * std::pow(kPistonArea / (kDischargeCoefficient * kOrificeArea), 2),
                   0.10));
  c.push_back(Case("weak magnet", Hidden::kWeakMagnet, "local_force_constant", "center", kWeakMagnetCentre, 0.05));
  c.push_back(Case("air gap along the track", Hidden::kAirGap, "force_constant_along_travel", "", 0.0, 0.0));
  c.push_back(Case("magnet temperature (extra column)", Hidden::kMagnetTemperature, "column_force_constant", "", 0.0,
                   0.0));
  c.push_back(Case("grease warm-up", Hidden::kWarmUp, "friction_warm_up", "time_constant", kThermalTimeConstant,
                   0.3));
  c.push_back(Case("back-EMF voltage limit", Hidden::kBackEmf, "drive_voltage_limit", "speed_slope", kEmfSlope, 0.15));
  // Issue 47: a force with memory, set by the stroke since the last reversal (the Bouc–Wen element's 90 % stroke).
  c.push_back(Case("hysteresis (a preloaded guide)", Hidden::kHysteresis, "hysteresis", "stroke",
                   kBoucWenDisplacement * (1.0 + std::log(5.0)), 0.25));
  // Issue 47: a vibration whose frequency drifts (its rate).
  c.push_back(Case("drifting vibration", Hidden::kDriftingVibration, "drifting_vibration", "drift_rate", kDriftRate,
                   0.1));
  // The same two on the rotary axis (rad, N·m): the stroke in radians, the drift in Hz/s.
  c.push_back(Case("rotary hysteresis", Hidden::kRotaryHysteresis, "hysteresis", "stroke",
                   kRadPerMetre * kBoucWenDisplacement * (1.0 + std::log(5.0)), 0.25));
  c.push_back(Case("rotary drifting vibration", Hidden::kRotaryDriftingVibration, "drifting_vibration", "drift_rate",
                   kDriftRate, 0.1));
  // Issue 47: a load behind a play, linear and rotary (the play's full width at the motor).
  c.push_back(Case("load behind a play", Hidden::kLoadBehindPlay, "backlash_load", "backlash", 2.0 * kGearHalfGap,
                   0.25));
  c.push_back(Case("rotary load behind a play", Hidden::kRotaryLoadBehindPlay, "backlash_load", "backlash",
                   2.0 * kGearHalfGap * kRadPerMetre, 0.25));
  CaseSpec stamps = Case("noisy stamps", Hidden::kPositionRipple, "position_periodic", "period", 0.006, 0.03);
  stamps.stamp_noise = 0.2;
  c.push_back(stamps);
  c.push_back(Case("nothing missing", Hidden::kNone, "", "", 0.0, 0.0));
  CaseSpec slow = Case("nothing missing, 100 Hz", Hidden::kNone, "", "", 0.0, 0.0);
  slow.sample_period = 0.01;
  c.push_back(slow);
  CaseSpec fast = Case("nothing missing, 2 kHz", Hidden::kNone, "", "", 0.0, 0.0);
  fast.sample_period = 0.0005;
  c.push_back(fast);
  return c;
}

double ControlPeriod(double sample_period) {
  const int per_sample = std::max(1, static_cast<int>(std::lround(sample_period / 1e-3)));
  return sample_period / per_sample;
}

double VelocityEstimateCutoffHz(double control_period) {
  const double alpha = control_period / (control_period + 1.0 / (kTwoPi * kVelocityEstimateHz));
  return -std::log(1.0 - alpha) / (kTwoPi * control_period);
}

Record Generate(Hidden hidden, const GeneratorSettings& settings) {
  std::mt19937 rng(settings.seed);
  Reference ref = MakeReference(settings.duration + 0.1, &rng);
  ref.continuous = settings.log_reference;
  std::uniform_real_distribution<double> jitter(-settings.jitter, settings.jitter);
  std::uniform_real_distribution<double> stamp_noise(-settings.stamp_noise, settings.stamp_noise);
  std::normal_distribution<double> noise(0.0, settings.force_noise);
  // The controller's steps per logged sample: 1 up to 1 kHz, else every k-th 1 ms step is logged.
  const double control_period = ControlPeriod(settings.sample_period);
  const int per_sample = static_cast<int>(std::lround(settings.sample_period / control_period));
  const auto n = static_cast<Eigen::Index>(settings.duration / settings.sample_period);
  Record r;
  r.rotary = IsRotary(hidden);
  r.time.resize(n); r.position.resize(n); r.force.resize(n); r.true_force.resize(n);
  r.extra_name = ExtraColumnName(hidden);
  if (!r.extra_name.empty()) r.extra.resize(n);
  if (settings.log_reference) {
    r.reference.resize(n); r.reference_velocity.resize(n); r.reference_acceleration.resize(n);
  }
  std::vector<double> command_time, command;  // for the delayed log
  State st;
  Controller pid;
  double now = 0.0;  // the plant's time [s]
  // What the drive makes of a command it applies at time `at`.
  const auto drive = [&](double command_value, double at) {
    double applied = command_value;
    if (Has(hidden, Hidden::kSaturation)) applied = std::clamp(applied, kLowerLimit, kUpperLimit);
    if (Has(hidden, Hidden::kForceRipple)) applied *= 1.0 + ForceConstantRipple(st.x);
    return applied * ForceConstantScale(hidden, at, st.x);
  };
  // The plant advanced to `until` under the commands sent so far.
  const auto advance_to = [&](double until) {
    if (!(until > now)) return;
    if (Has(hidden, Hidden::kActuatorLag)) {
      // Each command acts from kActuatorLag after it was sent until kActuatorLag after the next one: the step is split
      // where the applied command changes. (Taking the command active at the step's start made the lag 4 or 5 control
      // periods at random on a jittered clock, 4.5 on average, not the 4 ms this case hides.)
      for (double from = now; from < until;) {
        const auto it = std::upper_bound(command_time.begin(), command_time.end(), from - kActuatorLag + 1e-12);
        const std::size_t j = it == command_time.begin() ? 0 : static_cast<std::size_t>(it - command_time.begin()) - 1;
        const double to = it == command_time.end() ? until : std::min(until, *it + kActuatorLag);
        Advance(hidden, from, to - from, drive(command[j], from), &st);
        from = to;
      }
    } else {
      Advance(hidden, now, until - now, drive(command.back(), now), &st);
    }
    now = until;
  };
  const double scale = IsRotary(hidden) ? 1.0 / kRadPerMetre : 1.0;  // N → N·m on the rotary axis
  // Sample k of the log, taken at `at` (its time stamp's truth): the encoder's count, the command then in effect as the
  // amplifier reports it, the reference and the extra column.
  const auto record = [&](Eigen::Index k, double at) {
    const double x_measured = std::floor(st.x / settings.encoder_step) * settings.encoder_step;
    double logged = command.back();
    if (Has(hidden, Hidden::kDelay)) {  // the amplifier reports the force it applied kDelay ago (ZOH)
      const auto it = std::upper_bound(command_time.begin(), command_time.end(), at - kDelay);
      logged = it == command_time.begin() ? command.front() : command[static_cast<std::size_t>(it - command_time.begin() - 1)];
    }
    if (Has(hidden, Hidden::kMainsHum)) logged += kHumAmplitude * std::sin(kTwoPi * kHumHz * at + 0.2);
    r.time(k) = at + stamp_noise(rng) * settings.sample_period;
    r.position(k) = IsRotary(hidden) ? kRadPerMetre * (x_measured - 0.1) : x_measured;
    r.true_force(k) = scale * logged;
    r.force(k) = scale * (logged + noise(rng));
    if (settings.log_reference) ref.At(at, &r.reference(k), &r.reference_velocity(k), &r.reference_acceleration(k));
    if (Has(hidden, Hidden::kCoupledAxis)) r.extra(k) = OtherAxisAcceleration(at);
    if (Has(hidden, Hidden::kCoupledAxisVelocity)) r.extra(k) = OtherAxisVelocity(at);
    if (Has(hidden, Hidden::kIdleColumn)) r.extra(k) = HallTemperature(at);
    if (Has(hidden, Hidden::kOilTemperature)) r.extra(k) = OilTemperature(at);
    if (Has(hidden, Hidden::kMagnetTemperature)) r.extra(k) = MagnetTemperature(at);
  };
  // The controller runs on its own regular clock; a log at its rate is taken by a logger whose sampling instants
  // jitter about the same clock (±settings.jitter of the period, each stamped when taken): sample k at
  // k·T + offset(k), the first at 0. A slower log takes every per_sample-th control instant as it is.
  const auto steps = static_cast<Eigen::Index>(n) * per_sample;
  double offset_next = 0.0;  // of the next sample, drawn one step ahead: it may fall before that step's instant
  for (Eigen::Index step = 0; step < steps; ++step) {
    const double t = static_cast<double>(step) * control_period, next = t + control_period;
    const double offset = offset_next;
    offset_next = per_sample == 1 ? jitter(rng) * control_period : 0.0;
    const Eigen::Index k = step / per_sample;
    const bool logged_now = step % per_sample == 0;
    advance_to(t);
    const double x_measured = std::floor(st.x / settings.encoder_step) * settings.encoder_step;
    command.push_back(pid.Update(t, x_measured, ref));
    command_time.push_back(t);
    // A sample due at t and taken at or after it (one taken before it was recorded in the step before).
    if (logged_now && offset >= 0.0) {
      advance_to(t + offset);
      record(k, t + offset);
    }
    const Eigen::Index k_next = (step + 1) / per_sample;
    if (per_sample == 1 && offset_next < 0.0 && k_next < n) {
      advance_to(next + offset_next);
      record(k_next, next + offset_next);
    }
    advance_to(next);
  }
  return r;
}

void WriteCsv(const Record& record, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) throw std::runtime_error("WriteCsv: cannot write " + path);
  const bool extra = !record.extra_name.empty(), reference = record.reference.size() == record.time.size();
  std::fprintf(f, "%s%s%s%s\n", record.rotary ? "time_s,angle_rad,torque_Nm" : "time_s,position_m,force_N",
               extra ? "," : "", record.extra_name.c_str(),
               reference ? ",reference_m,reference_velocity_m_s,reference_acceleration_m_s2" : "");
  for (Eigen::Index i = 0; i < record.time.size(); ++i) {
    std::fprintf(f, "%.17g,%.17g,%.17g", record.time(i), record.position(i), record.force(i));
    if (extra) std::fprintf(f, ",%.17g", record.extra(i));
    if (reference) {
      std::fprintf(f, ",%.17g,%.17g,%.17g", record.reference(i), record.reference_velocity(i),
                   record.reference_acceleration(i));
    }
    std::fprintf(f, "\n");
  }
  if (std::fclose(f) != 0) throw std::runtime_error("WriteCsv: cannot write " + path);
}

namespace {

// Advances a load (xl, vl) joined to the carriage by `shaft` (its force on the load [N] with the carriage at (x, v))
// from sample i to i + 1: semi-implicit Euler on `steps` sub-steps, the carriage interpolated linearly, the load's
// bearing dragging `bearing` [N·s/m].
template <class Shaft>
void AdvanceLoad(const Shaft& shaft, double mass, double bearing, int steps, const Eigen::VectorXd& t,
                 const Eigen::VectorXd& x, const Eigen::VectorXd& v, Eigen::Index i, double* xl, double* vl) {
  const double h = (t(i + 1) - t(i)) / steps;
  for (int s = 0; s < steps; ++s) {
    const double q = static_cast<double>(s) / steps;
    const double xs = x(i) + q * (x(i + 1) - x(i)), vs = v(i) + q * (v(i + 1) - v(i));
    *vl += h * (shaft(xs, vs, *xl, *vl) - bearing * *vl) / mass;
    *xl += h * *vl;
  }
}

// TruthForce on the carriage's own coordinates (m, N).
Eigen::VectorXd CarriageForce(Hidden hidden, const Eigen::VectorXd& t, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& v, const Eigen::VectorXd& a, const Eigen::VectorXd* logged) {
  const Eigen::Index n = t.size();
  Eigen::VectorXd f(n);
  double far = x(0), xl = x(0), vl = 0.0, z = 0.0;
  const Load load;
  for (Eigen::Index i = 0; i < n; ++i) {
    f(i) = Mass(hidden, t(i)) * a(i) + FrictionLaw(hidden, v(i)) + kOffset + StatelessHidden(hidden, t(i), x(i), v(i));
    if (Has(hidden, Hidden::kHysteresis)) {
      if (i > 0) z = BoucWen(z, x(i) - x(i - 1));
      f(i) += BoucWenForce(z);
    }
    if (Has(hidden, Hidden::kInertiaRipple)) {
      f(i) += LinkageMass(x(i)) * a(i) + 0.5 * LinkageMassSlope(x(i)) * v(i) * v(i);
    }
    if (Has(hidden, Hidden::kBacklash)) {
      far = Play(x(i), far);
      f(i) += BacklashForce(x(i), far, v(i));
    }
    if (Has(hidden, Hidden::kLoadBehindPlay)) {
      f(i) += GearShaftForce(x(i), v(i), xl, vl);
      if (i + 1 < n) AdvanceLoad(GearShaftForce, kGearLoadMass, kGearBearing, 20, t, x, v, i, &xl, &vl);
    }
    if (Has(hidden, Hidden::kResonance)) {
      const auto shaft = [&load](double xs, double vs, double l, double lv) { return load.Force(xs, vs, l, lv); };
      f(i) += shaft(x(i), v(i), xl, vl);
      if (i + 1 < n) AdvanceLoad(shaft, kLoadMass, 0.0, 10, t, x, v, i, &xl, &vl);
    }
  }
  if (Has(hidden, Hidden::kForceRipple)) {  // the log holds the command, the force that acted over 1 + δ(x)
    for (Eigen::Index i = 0; i < n; ++i) f(i) /= 1.0 + ForceConstantRipple(x(i));
  }
  for (Eigen::Index i = 0; i < n; ++i) f(i) /= ForceConstantScale(hidden, t(i), x(i));  // 1 but for a force constant
  if (Has(hidden, Hidden::kMainsHum)) {
    for (Eigen::Index i = 0; i < n; ++i) f(i) += kHumAmplitude * std::sin(kTwoPi * kHumHz * t(i) + 0.2);
  }
  if (Has(hidden, Hidden::kSaturation) && logged != nullptr) {  // the log holds the command beyond what acted
    f += *logged - logged->cwiseMax(kLowerLimit).cwiseMin(kUpperLimit);
  }
  if (Has(hidden, Hidden::kBackEmf) && logged != nullptr) {  // beyond the steady-state voltage limit at each speed
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = (*logged)(i), shift = kEmfSlope * v(i);
      f(i) += u - std::clamp(u, -kStallForce - shift, kStallForce - shift);
    }
  }
  if (Has(hidden, Hidden::kActuatorLag)) {  // the log leads the applied force by the lag
    Eigen::VectorXd advanced(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double ta = t(i) + kActuatorLag;
      const auto it = std::upper_bound(t.data(), t.data() + n, ta);
      const Eigen::Index j = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(it - t.data()) - 1, 0, n - 2);
      const double q = std::clamp((ta - t(j)) / (t(j + 1) - t(j)), 0.0, 1.0);
      advanced(i) = (1.0 - q) * f(j) + q * f(j + 1);
    }
    return advanced;
  }
  if (!Has(hidden, Hidden::kDelay)) return f;
  Eigen::VectorXd delayed(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double td = t(i) - kDelay;
    const auto it = std::upper_bound(t.data(), t.data() + n, td);
    const Eigen::Index j = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(it - t.data()) - 1, 0, n - 2);
    const double q = std::clamp((td - t(j)) / (t(j + 1) - t(j)), 0.0, 1.0);
    delayed(i) = (1.0 - q) * f(j) + q * f(j + 1);
  }
  return delayed;
}

}  // namespace

bool IsRotary(Hidden hidden) {
  return hidden == Hidden::kGravity || hidden == Hidden::kRotaryHysteresis ||
         hidden == Hidden::kRotaryDriftingVibration || hidden == Hidden::kRotaryLoadBehindPlay;
}

bool OnlyInTheLoggedForce(Hidden hidden) { return hidden == Hidden::kDelay || hidden == Hidden::kMainsHum; }

std::string ExtraColumnName(Hidden hidden) {
  if (hidden == Hidden::kCoupledAxis) return "accel_y_m_s2";
  if (hidden == Hidden::kCoupledAxisVelocity) return "vel_y_m_s";
  if (hidden == Hidden::kIdleColumn) return "temperature_C";
  if (hidden == Hidden::kOilTemperature) return "oil_temperature_C";
  if (hidden == Hidden::kMagnetTemperature) return "magnet_temperature_C";
  return "";
}

Eigen::VectorXd TruthForce(Hidden hidden, const Eigen::VectorXd& t, const Eigen::VectorXd& angle_or_x,
                           const Eigen::VectorXd& v_in, const Eigen::VectorXd& a_in, const Eigen::VectorXd* logged) {
  if (IsRotary(hidden)) {  // the carriage's own coordinates, the force back to a torque
    const Eigen::VectorXd x = (angle_or_x.array() / kRadPerMetre + 0.1).matrix();
    const Eigen::VectorXd logged_force = logged ? Eigen::VectorXd(*logged * kRadPerMetre) : Eigen::VectorXd();
    return CarriageForce(hidden, t, x, v_in / kRadPerMetre, a_in / kRadPerMetre, logged ? &logged_force : nullptr) /
           kRadPerMetre;
  }
  return CarriageForce(hidden, t, angle_or_x, v_in, a_in, logged);
}

}  // namespace mb::independent
