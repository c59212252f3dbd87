#include "tools/workflow/residual_analysis.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace {

// Counts the lags outside the band and finds the strongest (τ = 0 skipped when `skip_zero`).
void Score(bool skip_zero, ResidualCorrelation* c) {
  for (std::size_t i = 0; i < c->lags.size(); ++i) {
    if (skip_zero && c->lags[i] == 0) continue;
    ++c->tested;
    const double v = c->values[i];
    if (std::abs(v) > c->band) ++c->outside;
    if (c->tested == 1 || std::abs(v) > std::abs(c->strongest)) {
      c->strongest = v;
      c->strongest_lag = c->lags[i];
    }
  }
}

std::string LagText(int lag, double sample_time) {
  std::string text = fmt::format("lag {} sample{}", lag, std::abs(lag) == 1 ? "" : "s");
  if (sample_time > 0.0) text += fmt::format(" = {:.4g} ms", 1e3 * lag * sample_time);
  return text;
}

}  // namespace

bool ResidualCorrelation::within_band() const {
  return static_cast<double>(outside) <= kResidMaxShareOutside * static_cast<double>(tested);
}

ResidualCorrelation ResidAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& residual, int max_lag) {
  const AutocorrelationTest test = ResidualAutocorrelation(residual, max_lag);
  ResidualCorrelation c;
  for (int lag = 0; lag <= max_lag; ++lag) {
    c.lags.push_back(lag);
    c.values.push_back(test.autocorrelation(lag));
  }
  c.band = test.band99;
  c.ljung_box_p = test.p_value;
  Score(true, &c);
  return c;
}

ResidualCorrelation ResidCrossCorrelation(const Eigen::Ref<const Eigen::VectorXd>& input,
                                          const Eigen::Ref<const Eigen::VectorXd>& residual, int max_lag) {
  const CrossCorrelationTest test = InputResidualCrossCorrelation(input, residual, max_lag);
  ResidualCorrelation c;
  for (Eigen::Index j = 0; j < test.lags.size(); ++j) {
    c.lags.push_back(test.lags(j));
    c.values.push_back(test.correlation(j));
  }
  c.band = test.band99;
  Score(false, &c);
  return c;
}

std::string DescribeWhiteness(const ResidualCorrelation& a, double sample_time) {
  std::string counts = fmt::format("{} of {} lags lie outside the 99 % band ±{:.3g} (strongest ρ = {:.3g} at {})",
                                   a.outside, a.tested, a.band, a.strongest, LagText(a.strongest_lag, sample_time));
  if (a.ljung_box_p >= 0.0) counts += fmt::format("; Ljung–Box p = {:.2g}", a.ljung_box_p);
  if (a.within_band()) return "The residual is white: " + counts + ": no structure in time is left.";
  return "The residual is not white: " + counts +
         ": the model leaves structure in time (a missing effect, unmodelled dynamics or coloured noise).";
}

std::string DescribeIndependence(const ResidualCorrelation& c, const std::string& input_name, double sample_time) {
  const std::string counts =
      fmt::format("{} of {} lags lie outside the 99 % band ±{:.3g} (strongest ρ = {:.3g} at {}{})", c.outside,
                  c.tested, c.band, c.strongest, LagText(c.strongest_lag, sample_time),
                  c.strongest_lag > 0 ? ", the residual after the input" : c.strongest_lag < 0 ? ", the residual before the input" : "");
  if (c.within_band()) {
    return fmt::format("The residual is independent of the {}: {}.", input_name, counts);
  }
  return fmt::format("The residual depends on the {}: {}: part of what the model misses is a function of the {} "
                     "(the band assumes a white residual, so with a coloured one it is only a guide).",
                     input_name, counts, input_name);
}

}  // namespace mb
