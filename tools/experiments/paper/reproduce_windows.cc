// reproduce, step 2: the training windows D(1..3) (eq. 25–26), every sample and a paper-size downsample.

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

void SelectWindows(ReproduceContext& c) {
  // 2. Windows D(1..3) (eq. 25–26), every sample and a paper-size downsample.
  c.Say(
      fmt::format("[2/{}] training windows D(1), D(2), D(3): L = 125, 225, 325 mm around each scan's centre", kSteps));
  json datasets;
  for (int k = 0; k < 3; ++k) {
    c.full[k] = SelectTrainingWindow(c.scans, kWindowLength[k]);
    const int factor =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(c.full[k].x.size()) / kPaperDatasetSize[k])));
    c.paper_size[k] = SelectTrainingWindow(c.scans, kWindowLength[k], factor);
    datasets[kWindowName[k]] = {{"window_m", kWindowLength[k]},
                                {"samples", c.full[k].x.size()},
                                {"paper_size_downsample", factor},
                                {"paper_size_samples", c.paper_size[k].x.size()},
                                {"paper_samples", kPaperDatasetSize[k]}};
  }
  c.results["configuration"]["datasets"] = datasets;
}

}  // namespace mb::paper
