#include "gapchain/output_file.hpp"

#include "scratch_files.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace gapchain;

namespace {

std::string aside_of(const fs::path& path) {
    return path.string() + ".gapchain-old." + std::to_string(::getpid());
}

} // namespace

TEST_CASE("OutputFile leaves nothing behind unless committed") {
    const fs::path dir = scratch::fresh_folder("output-file-atomic");
    const fs::path path = dir / "out.txt";
    {
        OutputFile f(path.string());
        f.stream() << "partial";
    }
    CHECK(fs::is_empty(dir));
    write_file_atomically(path.string(), "whole\n");
    CHECK(scratch::contents(path) == "whole\n");
    // A directory in the way: the rename's reason, not "a write failed" (its errno was lost).
    const fs::path folder = dir / "folder";
    fs::create_directories(folder);
    CHECK_THROWS_WITH_AS(write_file_atomically(folder.string(), "x\n"),
                         doctest::Contains("cannot write the output file: Is a directory"),
                         OutputError);
    fs::remove_all(dir);
}

TEST_CASE("a file set aside is put back unless kept") {
    const fs::path dir = scratch::fresh_folder("output-file-aside");
    const fs::path path = dir / "figure.png";
    write_file_atomically(path.string(), "previous\n");
    {
        SetAsideFile aside(path.string());
        CHECK_FALSE(fs::exists(path));
        CHECK(scratch::contents(aside_of(path)) == "previous\n");
        write_file_atomically(path.string(), "new\n");
    }
    CHECK(scratch::contents(path) == "previous\n");
    CHECK_FALSE(fs::exists(aside_of(path)));
    {
        SetAsideFile aside(path.string());
        write_file_atomically(path.string(), "new\n");
        aside.keep();
    }
    CHECK(scratch::contents(path) == "new\n");
    CHECK_FALSE(fs::exists(aside_of(path)));
    fs::remove_all(dir);
}

TEST_CASE("a path with nothing at it is left with nothing, and a moved-from file does nothing") {
    const fs::path dir = scratch::fresh_folder("output-file-none");
    const fs::path path = dir / "figure.png";
    {
        SetAsideFile aside(path.string());
        write_file_atomically(path.string(), "new\n");
        SetAsideFile moved(std::move(aside));
        CHECK(fs::exists(path)); // the moved-from object's destructor must not act
    }
    CHECK(fs::is_empty(dir));
    fs::remove_all(dir);
}

TEST_CASE("abandoning the unfinished outputs removes temporaries and puts files back") {
    // What a second signal's handler calls before it ends the process; here called directly.
    const fs::path dir = scratch::fresh_folder("output-file-abandon");
    const fs::path replaced = dir / "numbers.csv", added = dir / "figure.png";
    const fs::path written = dir / "summary.json";
    const std::string temporary = written.string() + ".tmp." + std::to_string(::getpid());
    write_file_atomically(replaced.string(), "previous\n");
    {
        SetAsideFile replaced_aside(replaced.string());
        SetAsideFile added_aside(added.string());
        write_file_atomically(replaced.string(), "new\n");
        write_file_atomically(added.string(), "new\n");
        OutputFile open_file(written.string());
        open_file.stream() << "partial";
        open_file.stream().flush();
        REQUIRE(fs::exists(temporary));
        abandon_unfinished_outputs();
        CHECK(scratch::contents(replaced) == "previous\n");
        CHECK_FALSE(fs::exists(added));
        CHECK_FALSE(fs::exists(aside_of(replaced)));
        CHECK_FALSE(fs::exists(temporary));
        // The process would end here; the destructors that follow are not part of the test.
    }
    // Outputs kept are no longer undone.
    const fs::path kept_path = dir / "kept.png";
    SetAsideFile kept(kept_path.string());
    write_file_atomically(kept_path.string(), "kept\n");
    kept.keep();
    abandon_unfinished_outputs();
    CHECK(scratch::contents(kept_path) == "kept\n");
    fs::remove_all(dir);
}
