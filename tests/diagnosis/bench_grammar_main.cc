// bench_grammar [--draws=300] [--noise=50] [--memory=0] [--first-seed=1] [--seeds=S1,S2,…] [--compare-only] [--out=DIR]
// [--verbose]:
// the grammar-draw benchmark (issue 45, item 6; tests/diagnosis/grammar_bench.h). Runs the draws of seeds first-seed …
// first-seed + draws − 1 (or those of --seeds, to rerun one cluster of the confusion table) and the noise-only draws
// kNoiseOnlySeedBase + 1 … + noise, then the draws with memory kMemorySeedBase + 1 … + memory (hysteresis, a load
// behind a play, a drifting vibration: issue 47, reported apart and written to memory.csv), prints each draw's
// progress on stderr and the report (Markdown) on stdout; writes
// results.csv and confusion.csv to DIR (out/bench-grammar). --verbose: each draw's named effects with their scores and
// compare's notes on stderr. `make bench-grammar` builds it in Release and runs it.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tests/diagnosis/grammar_bench.h"

namespace {

// "3,17,42" → {3, 17, 42}; throws std::invalid_argument naming the bad item.
std::vector<unsigned> ParseSeeds(const std::string& list) {
  std::vector<unsigned> seeds;
  std::size_t begin = 0;
  while (begin <= list.size()) {
    const std::size_t end = std::min(list.find(',', begin), list.size());
    const std::string item = list.substr(begin, end - begin);
    unsigned seed = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), seed);
    if (ec != std::errc() || ptr != item.data() + item.size() || item.empty()) {
      throw std::invalid_argument("--seeds: '" + item + "' is not a seed (a list of whole numbers: --seeds=3,17,42)");
    }
    seeds.push_back(seed);
    begin = end + 1;
  }
  return seeds;
}

void Write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  namespace g = mb::grammar;
  std::string out = "out/bench-grammar";
  int draws = 300, noise = 50, memory = 0;
  unsigned first = 1;
  std::vector<unsigned> seeds;
  bool improve = true, verbose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--compare-only") improve = false;
    else if (a == "--verbose") verbose = true;
    else if (a.rfind("--out=", 0) == 0) out = a.substr(6);
    else if (a.rfind("--draws=", 0) == 0) draws = std::stoi(a.substr(8));
    else if (a.rfind("--noise=", 0) == 0) noise = std::stoi(a.substr(8));
    else if (a.rfind("--memory=", 0) == 0) memory = std::stoi(a.substr(9));
    else if (a.rfind("--first-seed=", 0) == 0) first = static_cast<unsigned>(std::stoul(a.substr(13)));
    else if (a.rfind("--seeds=", 0) == 0) {
      try {
        seeds = ParseSeeds(a.substr(8));
      } catch (const std::invalid_argument& e) {
        std::cerr << "bench_grammar: " << e.what() << "\n";
        return 2;
      }
    } else {
      std::cerr << "bench_grammar: unknown argument '" << a
                << "'; usage: bench_grammar [--draws=300] [--noise=50] [--first-seed=1] [--seeds=S1,S2,…] "
                   "[--memory=0] [--compare-only] [--out=DIR] [--verbose]\n";
      return 2;
    }
  }
  if (!seeds.empty()) draws = static_cast<int>(seeds.size());  // the list's count, wherever --draws= stood
  try {
    std::vector<g::DrawResult> results, noise_results, memory_results;
    std::vector<std::string> not_drawn;  // seeds the generator cannot make a record of, with its reason
    const int total = draws + noise + memory;
    for (int i = 0; i < total; ++i) {
      const bool noise_only = i >= draws && i < draws + noise, with_memory = i >= draws + noise;
      const unsigned seed = with_memory  ? g::kMemorySeedBase + static_cast<unsigned>(i - draws - noise + 1)
                            : noise_only ? g::kNoiseOnlySeedBase + static_cast<unsigned>(i - draws + 1)
                            : seeds.empty() ? first + static_cast<unsigned>(i)
                                            : seeds[static_cast<std::size_t>(i)];
      const auto t0 = std::chrono::steady_clock::now();
      g::GrammarDraw draw;
      try {
        draw = g::Draw(seed);
      } catch (const std::logic_error& e) {  // the generator's own refusal (an effect that vanishes on its record)
        not_drawn.push_back(fmt::format("seed {}: {}", seed, e.what()));
        std::cerr << fmt::format("[{}/{}] seed {}: not drawn, left out of the counts: {}\n", i + 1, total, seed,
                                 e.what());
        continue;
      }
      g::DrawResult r;
      try {
        r = g::RunDraw(draw, std::filesystem::path(out) / fmt::format("seed_{}", seed), improve);
      } catch (const std::exception& e) {  // a draw the pipeline fails on is a miss, named with its seed, not the end
        r = g::DrawResult{};
        r.draw = draw;
        r.named_pair = "failed";
        r.details.push_back(fmt::format("failed: {}", e.what()));
        std::cerr << fmt::format("{}: FAILED: {}\n", draw.Describe(), e.what());
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::string verdict = noise_only ? (r.clean ? "clean" : "NAMED")
                                       : fmt::format("{}{}{}{}", r.named_right ? "named" : "NOT NAMED",
                                                     r.parameter_right ? ", parameter" : "",
                                                     r.third_found.empty() ? "" : ", amplitude with " + r.third_found,
                                                     r.improve_run ? (r.floor_reached ? ", floor" : ", NOT FLOOR") : "");
      std::cerr << fmt::format("[{}/{}] {} -> {} ({}; {}; {:.1f} s)\n", i + 1, total, draw.Describe(), r.named_pair,
                               r.named_first.empty() ? "nothing" : r.named_first, verdict, seconds);
      if (verbose) {
        for (const auto& line : r.details) std::cerr << "    " << line << "\n";
        if (r.improve_run) {
          std::cerr << fmt::format("    held out {:.4g} -> {:.4g}, floor {:.4g}\n", r.heldout_before, r.heldout_after,
                                   r.noise_floor);
        }
      }
      (with_memory ? memory_results : noise_only ? noise_results : results).push_back(std::move(r));
    }
    std::filesystem::create_directories(out);
    Write(std::filesystem::path(out) / "results.csv", g::ResultsCsv(results));
    Write(std::filesystem::path(out) / "noise_only.csv", g::ResultsCsv(noise_results));
    Write(std::filesystem::path(out) / "confusion.csv", g::ConfusionCsv(results));
    if (!results.empty() || !noise_results.empty()) std::cout << g::FormatReport(results, noise_results);
    if (!not_drawn.empty()) {
      std::cout << fmt::format("\n{} seed(s) not drawn (the generator refused them; left out of every count):\n",
                               not_drawn.size());
      for (const std::string& line : not_drawn) std::cout << "- " << line << "\n";
    }
    if (!memory_results.empty()) {
      Write(std::filesystem::path(out) / "memory.csv", g::ResultsCsv(memory_results));
      std::cout << "\n"
                << g::FormatReport(memory_results, {},
                                   "Draws with memory (hysteresis, a load behind a play, a drifting vibration)");
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_grammar: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
