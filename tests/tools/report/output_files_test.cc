// RefuseOutputsOverInputs (tools/report/output_files.h): an output file that is an input under any spelling (".."
// and ".", a symbolic link, a hard link), and an input lying in an output folder under a name the command writes
// there, are refused naming both; everything else passes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "tools/report/output_files.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// A fresh folder of this process holding one file "d.json".
fs::path Folder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "d.json") << "{}\n";
  return dir;
}

TEST(RefuseOutputsOverInputs, TheSameFileUnderAnotherSpellingIsRefusedNamingBoth) {
  const fs::path dir = Folder("mb_outputs_spelling");
  const fs::path input = dir / "d.json";
  const fs::path output = dir / "sub" / ".." / "." / "d.json";
  EXPECT_THAT([&] { RefuseOutputsOverInputs({{"DIAGRAM", input}}, {{"-o", output}}); },
              ThrowsMessage<OutputReplacesInputError>(HasSubstr(
                  "-o " + output.string() + " is the input DIAGRAM " + input.string() +
                  ": writing it would destroy the input; nothing was done: write the output elsewhere (another -o)")));
  // Relative to the working directory, the input need not exist yet for the check to hold.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  EXPECT_THROW(RefuseOutputsOverInputs({{"LOG", "t.csv"}}, {{"-o", fs::path(dir) / "t.csv"}}),
               OutputReplacesInputError);
  fs::current_path(cwd);
  fs::remove_all(dir);
}

TEST(RefuseOutputsOverInputs, SymbolicAndHardLinksToTheInputAreRefused) {
  const fs::path dir = Folder("mb_outputs_links");
  fs::create_symlink(dir / "d.json", dir / "link.json");
  fs::create_hard_link(dir / "d.json", dir / "hard.json");
  EXPECT_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "d.json"}}, {{"-o", dir / "link.json"}}),
               OutputReplacesInputError);
  EXPECT_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "link.json"}}, {{"-o", dir / "d.json"}}),
               OutputReplacesInputError);
  EXPECT_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "d.json"}}, {{"-o", dir / "hard.json"}}),
               OutputReplacesInputError);
  fs::remove_all(dir);
}

TEST(RefuseOutputsOverInputs, OtherFilesAndOptionsNotGivenPass) {
  const fs::path dir = Folder("mb_outputs_other");
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "d.json"}, {"--diagram", ""}},
                                          {{"-o", dir / "d.svg"}, {"--suggest", ""}},
                                          {{"--out", "", {"d.json"}}}));
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "d.json"}}, {{"-o", dir / "sub" / "d.json"}}));
  fs::remove_all(dir);
}

TEST(RefuseOutputsOverInputs, AnInputAmongTheFilesWrittenIntoAnOutputFolderIsRefused) {
  const fs::path dir = Folder("mb_outputs_folder");
  const std::vector<std::string> names{"compare.json", "report.html", "signal_*.png"};
  EXPECT_THAT(
      [&] { RefuseOutputsOverInputs({{"--measurement", dir / "compare.json"}}, {}, {{"--out", dir, names}}); },
      ThrowsMessage<OutputReplacesInputError>(HasSubstr(
          "--out " + dir.string() + " holds the input --measurement " + (dir / "compare.json").string() +
          ", and the command writes compare.json there: it would destroy the input; nothing was done: choose another "
          "--out folder")));
  EXPECT_THAT([&] { RefuseOutputsOverInputs({{"--input", dir / "signal_12.png"}}, {}, {{"--out", dir / ".", names}}); },
              ThrowsMessage<OutputReplacesInputError>(HasSubstr("writes signal_12.png (signal_*.png) there")));
  // The same name elsewhere, or another name in the folder: nothing is replaced.
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"--measurement", dir / "sub" / "compare.json"}}, {}, {{"--out", dir, names}}));
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"DIAGRAM", dir / "d.json"}}, {}, {{"--out", dir, names}}));
  fs::remove_all(dir);
}

// Issue 28: the gnuplot scripts and data go into plot/ of the output folder ("plot/*.dat"); an input there under such
// a name is refused as one in the folder itself, and only there ('*' is no '/'; plot/ reached through a link counts).
TEST(RefuseOutputsOverInputs, AnInputInANamedSubfolderOfAnOutputFolderIsRefused) {
  const fs::path dir = Folder("mb_outputs_subfolder");
  const std::vector<std::string> names{"report.html", "*.png", "plot/*.dat", "plot/gnuplot.log"};
  EXPECT_THAT([&] { RefuseOutputsOverInputs({{"--input", dir / "plot" / "a.dat"}}, {}, {{"--out", dir, names}}); },
              ThrowsMessage<OutputReplacesInputError>(HasSubstr(
                  "--out " + dir.string() + " holds the input --input " + (dir / "plot" / "a.dat").string() +
                  ", and the command writes plot/a.dat (plot/*.dat) there")));
  EXPECT_THAT([&] { RefuseOutputsOverInputs({{"LOG", dir / "sub/../plot/gnuplot.log"}}, {}, {{"--out", dir, names}}); },
              ThrowsMessage<OutputReplacesInputError>(HasSubstr("writes plot/gnuplot.log there")));
  fs::create_directories(dir / "elsewhere");
  fs::create_directory_symlink(dir / "elsewhere", dir / "sub" / "plot");
  EXPECT_THROW(RefuseOutputsOverInputs({{"--input", dir / "elsewhere" / "b.dat"}}, {}, {{"--out", dir / "sub", names}}),
               OutputReplacesInputError);
  // A name the folder holds is not one its subfolder holds, nor one deeper down, and the other way round.
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"--input", dir / "a.dat"}}, {}, {{"--out", dir, names}}));
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"--input", dir / "plot" / "x" / "a.dat"}}, {}, {{"--out", dir, names}}));
  EXPECT_NO_THROW(RefuseOutputsOverInputs({{"--input", dir / "plot" / "a.png"}}, {}, {{"--out", dir, names}}));
  fs::remove_all(dir);
}

// What an earlier run left: the named files in the folder and in its named subfolders, killed writers' temporary
// files included; nothing else (another name, another subfolder, a folder).
// Issue 41: a report written under o*?[x] lost its pictures in a browser ('?' and '#' end a URL's path) while the
// command exited 0; such a folder is refused before any work.
TEST(RefuseOutputsOverInputs, AFolderWhosePathBreaksTheReportsAddressIsRefused) {
  for (const std::string name : {"o*?[x]", "o#x", "runs/[a]", "a?b"}) {
    EXPECT_THAT([&] { RefuseOutputsOverInputs({{"DIAGRAM", "d.json"}}, {}, {{"--out", name, {"report.html"}}}); },
                ThrowsMessage<std::invalid_argument>(
                    HasSubstr("--out " + name + ": a report folder's path may not hold '?', '#', '*', '[' or ']'")))
        << name;
  }
  EXPECT_THAT([] { RequireReportFolderName("--out", "o*x"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("(it holds '*'): a browser takes '?' and '#' in the "
                                                             "report's address for the end of its path")));
  EXPECT_NO_THROW(RequireReportFolderName("--out", "out/run 1 (copy)"));
}

TEST(OutputFilesIn, FindsTheNamedFilesInTheFolderAndItsSubfolders) {
  const fs::path dir = Folder("mb_outputs_earlier");
  fs::create_directories(dir / "plot" / "deeper");
  fs::create_directories(dir / "other");
  fs::create_directories(dir / "x.png");  // a folder under a figure's name is no file
  for (const fs::path name : {"report.html", "s_1.png", "s_1.png.tmp123", "notes.txt", "plot/s_1.gp", "plot/s_1.dat",
                              "plot/gnuplot.log", "plot/keep.txt", "plot/deeper/s_2.gp", "other/s_3.gp"}) {
    std::ofstream(dir / name) << "x\n";
  }
  std::vector<fs::path> found =
      OutputFilesIn(dir, {"report.html", "*.png", "plot/*.gp", "plot/*.dat", "plot/gnuplot.log"});
  for (auto& path : found) path = path.lexically_relative(dir);
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<fs::path>{"plot/gnuplot.log", "plot/s_1.dat", "plot/s_1.gp", "report.html", "s_1.png",
                                          "s_1.png.tmp123"}));
  EXPECT_TRUE(OutputFilesIn(dir / "missing", {"report.html", "plot/*.gp"}).empty());
  fs::remove_all(dir);
}

TEST(FileNameMatches, StarStandsForAnyRunOfCharacters) {
  EXPECT_TRUE(FileNameMatches("compare.json", "compare.json"));
  EXPECT_FALSE(FileNameMatches("compare.json.bak", "compare.json"));
  EXPECT_TRUE(FileNameMatches("signal_0.png", "signal_*.png"));
  EXPECT_TRUE(FileNameMatches("signal_.png", "signal_*.png"));
  EXPECT_FALSE(FileNameMatches("signal_0.dat", "signal_*.png"));
  EXPECT_TRUE(FileNameMatches("a.b.png", "*.png"));
  EXPECT_FALSE(FileNameMatches("png", "*.png"));
}

}  // namespace
}  // namespace mb
