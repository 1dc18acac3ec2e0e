// The tools' shared run(): what SIGINT and SIGTERM do to the files a run is writing. Each case
// runs in a child process, since the signal handlers and the interrupt flag are process-wide.
#include "common/cli.hpp"

#include "gapchain/output_file.hpp"
#include "gapchain/report.hpp"

#include "scratch_files.hpp"

#include <doctest/doctest.h>

#include <csignal>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace gapchain;

namespace {

struct ChildEnd {
    pid_t pid = 0;
    int status = 0;
};

// Runs body inside cli::run() in a child process; returns its pid and wait status.
ChildEnd run_in_child(const std::function<void()>& body) {
    // Flushed first, or the child would write the parent's buffered output again.
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        // The tool's own message ("interrupted by ...") is not this test's output.
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
        CLI::App app{"signal test", "test-tool"};
        char name[] = "test-tool";
        char* argv[] = {name, nullptr};
        ::_exit(cli::run(app, 1, argv, body));
    }
    ChildEnd end{pid, 0};
    ::waitpid(pid, &end.status, 0);
    return end;
}

} // namespace

TEST_CASE("a signal that lands while a finished run writes its output leaves the file whole") {
    // The first signal removed the temporaries: the rename failed (exit 1) and the run was lost.
    const fs::path dir = scratch::fresh_folder("cli-first");
    const fs::path out = dir / "result.csv";
    for (const int sig : {SIGINT, SIGTERM}) {
        CAPTURE(sig);
        const ChildEnd end = run_in_child([&] {
            OutputFile file(out.string());
            file.stream() << "a,b\n";
            std::raise(sig);
            file.stream() << "1,2\n";
            file.commit();
        });
        REQUIRE(WIFEXITED(end.status));
        // The run was done: its file is whole and in place, and the run ends as interrupted.
        CHECK(WEXITSTATUS(end.status) == 128 + sig);
        CHECK(scratch::contents(out) == "a,b\n1,2\n");
        CHECK_FALSE(fs::exists(out.string() + ".tmp." + std::to_string(end.pid)));
    }
    fs::remove_all(dir);
}

TEST_CASE("the first signal cancels where the run asks, and its unfinished file is removed") {
    const fs::path dir = scratch::fresh_folder("cli-cancel");
    const fs::path out = dir / "result.csv";
    const ChildEnd end = run_in_child([&] {
        OutputFile file(out.string());
        file.stream() << "a,b\n";
        std::raise(SIGTERM);
        cli::throw_if_interrupted();
        file.commit();
    });
    REQUIRE(WIFEXITED(end.status));
    CHECK(WEXITSTATUS(end.status) == 128 + SIGTERM);
    CHECK_FALSE(fs::exists(out));
    CHECK(fs::is_empty(dir));
    fs::remove_all(dir);
}

TEST_CASE("a second signal ends the process at once and removes the temporaries") {
    // SIGINT then SIGTERM: the second ends the process whichever signal it is.
    for (const int second : {SIGINT, SIGTERM}) {
        CAPTURE(second);
        const fs::path dir = scratch::fresh_folder("cli-second");
        const fs::path out = dir / "result.csv";
        const ChildEnd end = run_in_child([&] {
            OutputFile file(out.string());
            file.stream() << "a,b\n";
            file.stream().flush();
            std::raise(SIGINT);
            std::raise(second);
            file.commit();
        });
        REQUIRE(WIFSIGNALED(end.status));
        CHECK(WTERMSIG(end.status) == second);
        // The temporary was there when the signals came (flushed); the handler removed it.
        CHECK(fs::is_empty(dir));
        fs::remove_all(dir);
    }
}

TEST_CASE("a second signal puts back the files a run had set aside to rewrite in place") {
    // Before, the handler removed only temporaries: the new file stayed at the path, and the
    // previous one stayed aside as FILE.gapchain-old.PID.
    const fs::path dir = scratch::fresh_folder("cli-aside");
    const fs::path numbers = dir / "result.json", figure = dir / "result.png";
    write_file_atomically(numbers.string(), "previous\n");
    const ChildEnd end = run_in_child([&] {
        cli::Outputs outputs({});
        outputs.replacing(numbers.string());
        outputs.replacing(figure.string());
        write_file_atomically(numbers.string(), "new\n");
        write_file_atomically(figure.string(), "half a figure");
        std::raise(SIGTERM);
        std::raise(SIGTERM);
        outputs.keep();
    });
    REQUIRE(WIFSIGNALED(end.status));
    CHECK(WTERMSIG(end.status) == SIGTERM);
    CHECK(scratch::contents(numbers) == "previous\n");
    CHECK_FALSE(fs::exists(figure));
    CHECK_FALSE(fs::exists(numbers.string() + ".gapchain-old." + std::to_string(end.pid)));
    fs::remove_all(dir);
}
