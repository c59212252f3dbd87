// Bounded reads (engine/input_file.h, issue 30): only regular files within the size limit reach a reader; a device
// or a FIFO is refused from its status without being opened (a FIFO with no writer would block the open).

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/table.h"
#include "tests/error_message.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ErrorOf;

class InputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mb_input_file_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "log.csv") << "time_s,y\n0,1\n1,2\n";
  }
  void TearDown() override {
    SetMaxInputFileBytes(kDefaultMaxInputFileBytes);
    fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_F(InputFiles, ARegularFileIsReadWhole) {
  EXPECT_EQ(ReadInputFile(dir_ / "log.csv", "measurement log"), "time_s,y\n0,1\n1,2\n");
}

TEST_F(InputFiles, DevicesAreRefusedBeforeTheyAreRead) {
  EXPECT_EQ(ErrorOf<std::invalid_argument>([] { ReadInputFile("/dev/zero", "measurement log"); }),
            "/dev/zero: the measurement log is a character device, not a regular file; give the path of a regular "
            "file (save a stream or a pipe's output to a file first)");
  EXPECT_EQ(ErrorOf<std::invalid_argument>([] { ReadDiagramJson("/dev/urandom"); }),
            "/dev/urandom: the diagram file is a character device, not a regular file; give the path of a regular "
            "file (save a stream or a pipe's output to a file first)");
  EXPECT_THAT(ErrorOf<std::invalid_argument>([&] { ReadTable(dir_.string(), TableReadOptions{{}, "table"}); }),
              HasSubstr(": the table is a folder, not a regular file"));
}

TEST_F(InputFiles, AFifoWithoutWriterIsRefusedNotOpened) {
  const fs::path fifo = dir_ / "pipe.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Opening it would block this test forever: the check must come from its status alone.
  EXPECT_EQ(ErrorOf<std::invalid_argument>([&] { ReadInputFile(fifo, "measurement log"); }),
            fifo.string() + ": the measurement log is a FIFO (named pipe), not a regular file; give the path of a "
                            "regular file (save a stream or a pipe's output to a file first)");
  const fs::path link = dir_ / "zero.json";
  fs::create_symlink("/dev/zero", link);
  EXPECT_THAT(ErrorOf<std::invalid_argument>([&] { ReadDiagramJson(link); }),
              HasSubstr("zero.json: the diagram file is a character device, not a regular file"));
}

TEST_F(InputFiles, AFileAboveTheLimitIsRefusedNamingTheFlag) {
  SetMaxInputFileBytes(10);
  EXPECT_EQ(ErrorOf<std::invalid_argument>([&] { ReadInputFile(dir_ / "log.csv", "measurement log"); }),
            (dir_ / "log.csv").string() +
                ": the measurement log is 17 bytes (1.7e-05 MB), more than the input limit of 1e-05 MB (10 bytes); "
                "if it is meant to be this large, raise the limit with --max-input-mb (e.g. --max-input-mb 2)");
  SetMaxInputFileBytes(17);
  EXPECT_EQ(ReadInputFile(dir_ / "log.csv", "measurement log").size(), 17U);
  EXPECT_THROW(SetMaxInputFileBytes(0), std::invalid_argument);
}

TEST_F(InputFiles, AMissingFileIsAnOpenErrorInTheReadersWords) {
  EXPECT_EQ(ErrorOf<FileOpenError>([&] { ReadInputFile(dir_ / "none.csv", "measurement log"); }),
            (dir_ / "none.csv").string() + ": cannot open the measurement log (missing file or no permission); check "
                                           "the path");
  EXPECT_EQ(ErrorOf<FileOpenError>([&] { ReadDiagramJson(dir_ / "none.json"); }),
            (dir_ / "none.json").string() + ": cannot open the diagram file (does it exist?)");
}

}  // namespace
}  // namespace mb
