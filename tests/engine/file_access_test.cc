// Files a diagram may read (engine/file_access.h) and how outputs are written (engine/output_file.h): a diagram
// from someone else reads nothing outside its folder, no device, no FIFO; an output never replaces a non-file.

#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "engine/output_file.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using nlohmann::json;

class DiagramFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("mb_file_access_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    dir_ = root_ / "diagram";
    fs::create_directories(dir_);
    fs::create_directories(root_ / "elsewhere");
    std::ofstream(root_ / "elsewhere" / "profile.csv") << "time_s,y\n0,1\n1,2\n";
    std::ofstream(dir_ / "profile.csv") << "time_s,y\n0,1\n1,2\n";
    ClearAllowedDiagramFileFolders();
  }
  void TearDown() override {
    ClearAllowedDiagramFileFolders();
    fs::remove_all(root_);
  }
  // A diagram whose from_file element reads `file`.
  static json FromFileDiagram(const std::string& file) {
    return {{"schemaVersion", "1.0"},
            {"name", "t"},
            {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}}},
            {"solver", {{"type", "rk4"}, {"step", 0.1}}},
            {"elements", {{{"name", "f"}, {"type", "from_file"}, {"parameters", {{"file", file}, {"column", "y"}}}}}}};
  }
  std::string BuildError(const json& j) {
    try {
      BuildDiagram(j, dir_, "d.json");
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }
  static std::string BuildDiagramError(const json& j, const fs::path& folder) {
    try {
      BuildDiagram(j, folder, "copy.json");
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path root_, dir_;
};

// A diagram written to another folder (compare --suggest, improve) still names its files: RelocateFiles rewrites
// them against the new folder, and says which now lie outside it (the copy reads those only with --allow-path).
TEST_F(DiagramFiles, ADiagramWrittenElsewhereNamesTheSameFiles) {
  const fs::path target = root_ / "elsewhere";
  DiagramDocument document(FromFileDiagram("profile.csv"), dir_, "d.json");
  EXPECT_THAT(BuildError(document.json()), Not(HasSubstr("profile.csv")));  // read from dir_: fine
  EXPECT_THAT(BuildError(FromFileDiagram("profile.csv")), Not(HasSubstr("profile.csv")));
  const std::vector<std::string> outside = document.RelocateFiles(target);
  EXPECT_EQ(document.json()["elements"][0]["parameters"]["file"], "../diagram/profile.csv");
  EXPECT_THAT(outside, ::testing::ElementsAre("f.file: ../diagram/profile.csv"));
  // Loaded from the new folder, it reads the original file once that folder is allowed; unrelocated, "profile.csv"
  // would have read elsewhere/profile.csv, another file.
  EXPECT_THAT(BuildDiagramError(document.json(), target), HasSubstr("outside the diagram's folder"));
  AllowDiagramFilesUnder(dir_);
  EXPECT_EQ(BuildDiagramError(document.json(), target), "no error");
}

TEST_F(DiagramFiles, ADiagramWrittenBesideItsFileNeedsNoAllowedFolder) {
  const fs::path target = root_ / "elsewhere";
  DiagramDocument document(FromFileDiagram((target / "profile.csv").string()), dir_, "d.json");
  EXPECT_TRUE(document.RelocateFiles(target).empty());
  EXPECT_EQ(document.json()["elements"][0]["parameters"]["file"], "profile.csv");  // absolute inside → relative
  EXPECT_EQ(BuildDiagramError(document.json(), target), "no error");
}

TEST_F(DiagramFiles, AFileBesideTheDiagramIsRead) {
  EXPECT_NO_THROW(BuildDiagram(FromFileDiagram("profile.csv"), dir_, "d.json"));
  EXPECT_EQ(ResolveDiagramFile("profile.csv", dir_), fs::canonical(dir_ / "profile.csv"));
}

TEST_F(DiagramFiles, APathThatEscapesTheFolderIsRefusedWithoutShowingTheFile) {
  const std::string e = BuildError(FromFileDiagram("../../../../../../../../etc/passwd"));
  EXPECT_THAT(e, HasSubstr("/elements/0: element 'f' (from_file): parameter file \"../../../../../../../../etc/passwd\" "
                           "resolves to /etc/passwd, outside the diagram's folder"));
  EXPECT_THAT(e, HasSubstr("--allow-path /etc"));
  EXPECT_THAT(e, Not(HasSubstr("root:")));  // never the file's content
  EXPECT_THAT(BuildError(FromFileDiagram((root_ / "elsewhere" / "profile.csv").string())),
              HasSubstr("outside the diagram's folder"));
}

TEST_F(DiagramFiles, ASymbolicLinkOutOfTheFolderIsRefused) {
  fs::create_symlink(root_ / "elsewhere" / "profile.csv", dir_ / "link.csv");
  EXPECT_THAT(BuildError(FromFileDiagram("link.csv")), HasSubstr("outside the diagram's folder"));
  fs::create_symlink("/dev/zero", dir_ / "zero.csv");
  EXPECT_THAT(BuildError(FromFileDiagram("zero.csv")), HasSubstr("resolves to /dev/zero, outside"));
}

TEST_F(DiagramFiles, DevicesAndFifosAreNotRead) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.csv").c_str(), 0600), 0);
  EXPECT_THAT(BuildError(FromFileDiagram("pipe.csv")), HasSubstr("is not a regular file"));  // would block forever
  AllowDiagramFilesUnder("/dev");
  EXPECT_THAT(BuildError(FromFileDiagram("/dev/zero")), HasSubstr("\"/dev/zero\" (/dev/zero) is not a regular file"));
  EXPECT_THAT(BuildError(FromFileDiagram("missing.csv")), HasSubstr("no such file"));
}

TEST_F(DiagramFiles, AnAllowedFolderMayBeRead) {
  const json j = FromFileDiagram("../elsewhere/profile.csv");
  EXPECT_THAT(BuildError(j), HasSubstr("outside the diagram's folder"));
  AllowDiagramFilesUnder(root_ / "elsewhere");
  EXPECT_NO_THROW(BuildDiagram(j, dir_, "d.json"));
  EXPECT_THROW(AllowDiagramFilesUnder(root_ / "no_such_folder"), std::invalid_argument);
}

TEST_F(DiagramFiles, ASubsystemFileOutsideTheFolderIsRefused) {
  std::ofstream(root_ / "elsewhere" / "inner.json") << FromFileDiagram("profile.csv").dump();
  const json j = {{"schemaVersion", "1.0"},
                  {"name", "outer"},
                  {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}}},
                  {"elements", {{{"name", "s"}, {"type", "subsystem"}, {"diagram", "../elsewhere/inner.json"}}}}};
  EXPECT_THAT(BuildError(j), HasSubstr("/elements/0/diagram: \"../elsewhere/inner.json\" resolves to"));
  EXPECT_THAT(BuildError(j), HasSubstr("outside the diagram's folder"));
}

// ---- Output files ----------------------------------------------------------------------------------------

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(DiagramFiles, AnOutputReplacesARegularFileAndLeavesNothingElse) {
  const fs::path out = root_ / "out";
  fs::create_directories(out);
  WriteFileSafely(out / "model.json", "first\n");
  WriteFileSafely(out / "model.json", "second\n");
  EXPECT_EQ(ReadAll(out / "model.json"), "second\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator{}), 1);  // no temporary left
}

TEST_F(DiagramFiles, AnOutputThroughASymbolicLinkKeepsTheLink) {
  const fs::path out = root_ / "out";
  fs::create_directories(out);
  std::ofstream(out / "target.json") << "old";
  fs::create_symlink(out / "target.json", out / "link.json");
  WriteFileSafely(out / "link.json", "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(out / "link.json")));
  EXPECT_EQ(ReadAll(out / "target.json"), "new");
  fs::create_symlink(out / "nothing.json", out / "dangling.json");
  EXPECT_THROW(WriteFileSafely(out / "dangling.json", "x"), std::runtime_error);
}

TEST_F(DiagramFiles, AnOutputIntoAFifoOrDeviceIsWrittenThroughNeverReplaced) {
  const fs::path fifo = root_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadAll(fifo); });
  // The reader thread may not have opened the FIFO yet: until it has, the output is refused (no reader), not
  // waited for.
  for (int attempt = 0;; ++attempt) {
    try {
      WriteFileSafely(fifo, "through the pipe");
      break;
    } catch (const std::runtime_error& e) {
      ASSERT_THAT(e.what(), HasSubstr("that no process reads"));
      ASSERT_LT(attempt, 500) << "the reader never opened the FIFO";
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fs::status(fifo)));
  WriteFileSafely("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file(fs::status("/dev/null")));
  try {
    WriteFileSafely(root_, "x");
    ADD_FAILURE() << "a folder was accepted as an output";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("is a folder, not a file"));
  }
}

// Issue 41: draw -o FIFO waited forever for a reader; a FIFO nobody reads is refused at once, nothing written.
TEST_F(DiagramFiles, AnOutputIntoAFifoThatNobodyReadsIsRefusedAtOnce) {
  const fs::path out = root_ / "out";
  fs::create_directories(out);
  const fs::path fifo = out / "unread";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  try {
    WriteFileSafely(fifo, "nobody listens");
    ADD_FAILURE() << "a FIFO without a reader was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), fifo.string() + " is a FIFO (named pipe) that no process reads: writing to it "
                                                      "would wait forever; start its reader first, or give a file "
                                                      "name");
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  EXPECT_TRUE(fs::is_fifo(fs::status(fifo)));
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator{}), 1);  // no temporary beside it
}

}  // namespace
}  // namespace mb
