#include "tools/report/residual_figures.h"

#include <fmt/format.h>

#include "models/diagnosis/periodogram.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace fs = std::filesystem;

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

void AddResidualFigures(HtmlReport* report, const fs::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const DiagnosisResult* diagnosis, const std::string& position_column) {
  const auto t = ToStd(log.time());
  Figure overlay{"model_vs_measurement.png", fmt::format("{}: measured vs model", before.connector), "time [s]",
                 fmt::format("{} [{}]", before.connector, before.unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model", "lines"});
  overlay.x_link = "time";
  report->AddFigure(overlay, out);

  Figure rt{"residual_vs_time.png", "Residual against time (after the fit)", "time [s]",
            fmt::format("measured − model [{}]", before.unit), {}};
  rt.series.push_back({t, ToStd(residual_after), "residual", "lines"});
  rt.x_link = "time";
  report->AddFigure(rt, out);
  if (log.has_column(position_column)) {
    Figure rx{"residual_vs_position.png", "Residual against position", "position [m]",
              fmt::format("residual [{}]", before.unit), {}};
    rx.series.push_back({ToStd(log.column(position_column)), ToStd(residual_after), "residual", "dots"});
    report->AddFigure(rx, out);
  }
  const std::string velocity_column = DerivedVelocityColumn(position_column);
  const std::string acceleration_column = DerivedAccelerationColumn(position_column);
  if (log.has_column(velocity_column)) {
    const BinnedResidual b = BinResidual(log.column(velocity_column), residual_after, 40);
    std::vector<double> xs, ys;
    for (Eigen::Index i = 0; i < b.centers.size(); ++i) {
      if (b.count(i) > 0) {
        xs.push_back(b.centers(i));
        ys.push_back(b.mean(i));
      }
    }
    Figure rv{"residual_vs_velocity.png", "Residual against velocity (binned mean: the friction shape)",
              "velocity [m/s]", fmt::format("residual [{}]", before.unit), {}};
    rv.series.push_back({ToStd(log.column(velocity_column)), ToStd(residual_after), "samples", "dots"});
    rv.series.push_back({xs, ys, "bin mean", "lines"});
    report->AddFigure(rv, out);
  }
  if (log.has_column(acceleration_column)) {
    Figure ra{"residual_vs_acceleration.png", "Residual against acceleration (a slope: mass mismatch)",
              "acceleration [m/s²]", fmt::format("residual [{}]", before.unit), {}};
    ra.series.push_back({ToStd(log.column(acceleration_column)), ToStd(residual_after), "samples", "dots"});
    report->AddFigure(ra, out);
  }
  if (diagnosis && !diagnosis->position_peaks.empty()) {
    // Re-plot the periodogram from the peaks list is too sparse; compute the full one here for the figure.
    const Periodogram pg = PositionPeriodogram(log.column(position_column), residual_after);
    Figure fp{"position_periodogram.png", "Position-domain periodogram of the residual (share of variance explained)",
              "period [m]", "power", {}};
    fp.log_x = true;
    fp.series.push_back({ToStd(pg.periods), ToStd(pg.power), "floating-mean Lomb–Scargle", "lines"});
    for (const auto& e : diagnosis->effects) {  // the periods the ranking chose, where the text names them
      const auto period = e.parameters.find("period");
      if (period != e.parameters.end()) {
        const std::string unit = PositionUnitToken(position_column);
        fp.x_marks.emplace_back(period->second, unit == "m" ? fmt::format("{} {:.4g} mm", e.effect, 1e3 * period->second)
                                                            : fmt::format("{} {:.4g} {}", e.effect, period->second, unit));
      }
    }
    report->AddFigure(fp, out);
  }
}

void AddBeforeAfterFigures(HtmlReport* report, const fs::path& out, const std::string& prefix,
                           const std::string& record, const MeasurementLog& log, const ComparedOutput& before,
                           const ComparedOutput& after, const std::string& position_column) {
  const auto t = ToStd(log.time());
  const std::string unit = before.unit;
  Figure overlay{prefix + "model_vs_measurement.png",
                 fmt::format("{}: measured {} vs model, before (step 0) and after (improved)", record, before.connector),
                 "time [s]", fmt::format("{} [{}]", before.connector, unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model before", "lines"});
  overlay.series.push_back({t, ToStd(after.model), "model after", "lines"});
  overlay.x_link = prefix + "time";
  report->AddFigure(overlay, out);

  const auto r_before = ToStd(before.residual()), r_after = ToStd(after.residual());
  Figure rt{prefix + "residual_vs_time.png", record + ": residual against time, before vs after", "time [s]",
            fmt::format("measured − model [{}]", unit), {}};
  rt.series.push_back({t, r_before, "before", "lines"});
  rt.series.push_back({t, r_after, "after", "lines"});
  rt.x_link = prefix + "time";
  report->AddFigure(rt, out);
  // The residual against a logged column (position, velocity), before and after on the same axes.
  const auto against = [&](const std::string& column, const std::string& quantity, const std::string& axis_unit) {
    if (!log.has_column(column)) return;
    const auto abscissa = ToStd(log.column(column));
    Figure f{fmt::format("{}residual_vs_{}.png", prefix, quantity),
             fmt::format("{}: residual against {}, before vs after", record, quantity),
             fmt::format("{} [{}]", quantity, axis_unit), fmt::format("residual [{}]", unit), {}};
    f.series.push_back({abscissa, r_before, "before", "dots"});
    f.series.push_back({abscissa, r_after, "after", "dots"});
    report->AddFigure(f, out);
  };
  const std::string position_unit = PositionUnitToken(position_column);
  against(position_column, "position", position_unit);
  against(DerivedVelocityColumn(position_column), "velocity", position_unit + "/s");
}

}  // namespace mb
