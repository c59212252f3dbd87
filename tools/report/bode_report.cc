#include "tools/report/bode_report.h"

#include <string>
#include <vector>

#include <fmt/format.h>

#include "tools/report/report.h"

namespace mb {

std::vector<std::string> BodeReportFileNames() {
  std::vector<std::string> names{"report.html"};
  for (const auto& name : FigureFileNames("bode_*.png")) names.push_back(name);
  return names;
}

void WriteBodeReport(const LinearModel& model, const Eigen::VectorXd& frequency_hz, const std::string& title,
                     const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  HtmlReport report(title, InteractiveCharts{});
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < model.input_names.size(); ++i) {
    rows.push_back({"input", model.input_names[i], fmt::format("{:.6g}", model.u0(static_cast<Eigen::Index>(i))),
                    model.input_units[i]});
  }
  for (std::size_t i = 0; i < model.output_names.size(); ++i) {
    rows.push_back({"output", model.output_names[i], fmt::format("{:.6g}", model.y0(static_cast<Eigen::Index>(i))),
                    model.output_units[i]});
  }
  for (std::size_t i = 0; i < model.state_names.size(); ++i) {
    rows.push_back({"state", model.state_names[i], fmt::format("{:.6g}", model.x0(static_cast<Eigen::Index>(i))), ""});
  }
  report.Paragraph(fmt::format("Linearised at t = {} s: ẋ = A x + B u, y = C x + D u with {} states, {} inputs and {} "
                               "outputs (discrete blocks hold their outputs). The operating point:",
                               model.time, model.a.rows(), model.b.cols(), model.c.rows()));
  report.Table({"kind", "name", "value", "unit"}, rows);
  const std::vector<double> x(frequency_hz.begin(), frequency_hz.end());
  Figure gain{"bode_gain.png", "Gain", "frequency [Hz]", "gain [dB]", {}};
  Figure phase{"bode_phase.png", "Phase", "frequency [Hz]", "phase [deg]", {}};
  for (Eigen::Index o = 0; o < model.d.rows(); ++o) {
    for (Eigen::Index i = 0; i < model.d.cols(); ++i) {
      const BodeData bode = ToBode(model.FrequencyResponse(static_cast<int>(o), static_cast<int>(i), frequency_hz));
      const std::string label = fmt::format("{} / {} [{}/{}]", model.output_names[static_cast<std::size_t>(o)],
                                            model.input_names[static_cast<std::size_t>(i)],
                                            model.output_units[static_cast<std::size_t>(o)],
                                            model.input_units[static_cast<std::size_t>(i)]);
      gain.series.push_back({x, std::vector<double>(bode.gain_db.begin(), bode.gain_db.end()), label, "lines"});
      phase.series.push_back({x, std::vector<double>(bode.phase_deg.begin(), bode.phase_deg.end()), label, "lines"});
    }
  }
  for (Figure* f : {&gain, &phase}) {
    f->log_x = true;
    f->x_link = "frequency";
    if (!f->series.empty()) report.AddFigure(*f, folder);
  }
  if (gain.series.empty()) report.Paragraph("No Bode plot: the diagram has no input or no output connector.");
  report.Write(folder / "report.html");
}

}  // namespace mb
