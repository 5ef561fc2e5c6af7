// core/file_io: the check every front end makes before it renders, that an output can be written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "file_io.h"

namespace partita {
namespace {

namespace fs = std::filesystem;

TEST(FileIo, AnOutputIsCheckedBeforeAnyWork) {
    fs::path dir = fs::temp_directory_path() / ("partita-file-io-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    EXPECT_NO_THROW(requireOutputFolder(dir / "x.exr"));
    EXPECT_NO_THROW(requireOutputFolder("x.exr")) << "a bare name is in the working folder";
    try {
        requireOutputFolder(dir / "missing" / "x.exr");
        ADD_FAILURE() << "a missing folder passes";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("folder '" + (dir / "missing").string() +
                                             "' does not exist"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(requireOutputFolder(dir), std::runtime_error) << "a folder is not a file";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace partita
